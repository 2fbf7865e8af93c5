// Draco .drc writer (internal to fq_io; use write_mesh).
#pragma once

#include <cstdint>
#include <string>

#include "core/mesh_view.h"
#include "common/status.h"

namespace fq::io {

/// Encodes with draco::Encoder; labels (checked by the caller) as a GENERIC uint32
/// attribute named by metadata. position_bits: 1..30, 0 = no quantization.
Status write_drc(const std::string& path, const MeshView& mesh, const uint32_t* labels, uint32_t num_clusters,
                 int position_bits);

}  // namespace fq::io
