// Our binary PLY writer (internal to fq_io; use write_mesh).
#pragma once

#include <cstdint>
#include <string>

#include "common/status.h"
#include "core/mesh_view.h"
#include "io/mesh_attributes.h"

namespace fq::io {

/// Binary little-endian PLY: `float x, y, z`, then the kept vertex properties of
/// `attributes` (may be null) in their types; with labels also `uint label` and
/// `uchar cluster_red, cluster_green, cluster_blue`. `red, green, blue` hold the input's
/// colours when it had them, else (with labels) the cluster colours; `colour_clusters`
/// puts the cluster colours there in any case. Faces: `list uchar int vertex_indices`,
/// then the kept face properties. Labels are assumed checked by the caller.
Status write_ply(const std::string& path, const MeshView& mesh, const uint32_t* labels,
                 const MeshAttributes* attributes = nullptr, bool colour_clusters = false);

}  // namespace fq::io
