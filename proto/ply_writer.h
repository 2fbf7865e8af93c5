// Our binary PLY writer (internal to fq_meshio; use write_mesh).
#pragma once

#include <cstdint>
#include <string>

#include "kernels/mesh_view.h"
#include "common/status.h"

namespace fq::io {

/// Binary little-endian PLY with optional per-vertex label and colour. Labels are
/// assumed checked by the caller.
Status write_ply(const std::string& path, const MeshView& mesh, const uint32_t* labels);

}  // namespace fq::io
