// What an OBJ carries per triangle corner, kept beside the welded mesh (internal to fq_io;
// use read_mesh): texture coordinates (`vt`), normals (`vn`), the material library (`mtllib`)
// and each triangle's material (`usemtl`).
#pragma once

#include <string>

#include "io/mesh_attributes.h"

namespace draco {
class Mesh;
}

namespace fq::io {

/// Fills attributes.corner_uv, corner_normal and materials from `dm`, an OBJ decoded by Draco
/// with metadata (use_metadata), whose faces are the welded mesh's triangles in order. `path`
/// is the OBJ's: a relative `mtllib` is kept as a path from its folder.
void keep_obj_corners(const draco::Mesh& dm, const std::string& path, MeshAttributes& attributes);

}  // namespace fq::io
