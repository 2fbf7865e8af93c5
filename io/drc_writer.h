// Draco .drc writer (internal to fq_io; use write_mesh).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "common/status.h"
#include "core/mesh_view.h"
#include "io/mesh_attributes.h"

namespace fq::io {

/// Encodes with draco::Encoder; labels (checked by the caller) as a GENERIC uint32
/// attribute named by metadata. position_bits: 1..30, 0 = no quantization (only positions
/// are quantized). Of `attributes` (may be null), the vertex normals (nx, ny, nz), colours
/// (red, green, blue[, alpha]; uchar stays uchar) and texture coordinates go to Draco's
/// NORMAL, COLOR and TEX_COORD attributes; what else they hold is named in `dropped`.
Status write_drc(const std::string& path, const MeshView& mesh, const uint32_t* labels, uint32_t num_clusters,
                 int position_bits, const MeshAttributes* attributes, std::vector<std::string>& dropped);

}  // namespace fq::io
