// Our OBJ writer (internal to fq_io; use write_mesh). Why not assimp's, which writes our
// glb: its OBJ exporter writes a material library of its own, named after the output and
// made from assimp's material model, and without one it writes no `usemtl` lines; keeping
// the input's library as it is, and each triangle's material, texture coordinates and
// normals as they were, needs lines of our own. OBJ's are few and plain.
#pragma once

#include <string>
#include <vector>

#include "common/status.h"
#include "core/mesh_view.h"
#include "io/mesh_attributes.h"

namespace fq::io {

/// `v` lines in vertex order; `vt` and `vn` lines of the per-corner values (or of the
/// per-vertex u, v and nx, ny, nz properties); `mtllib` naming the input's library by its
/// path from the output's folder, and `usemtl` wherever the material changes along the
/// triangles; `f v/vt/vn` lines. What OBJ cannot hold (colours, labels, other properties)
/// goes to `dropped`, one phrase a group.
Status write_obj(const std::string& path, const MeshView& mesh, const uint32_t* labels,
                 const MeshAttributes* attributes, std::vector<std::string>& dropped);

}  // namespace fq::io
