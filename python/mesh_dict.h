// fq.Mesh's arrays (fq/mesh.py) <-> a mesh and its io::MeshAttributes, for read_mesh and
// write_mesh. Copies, with the GIL held.
#pragma once

#include <pybind11/numpy.h>

#include <string>
#include <vector>

#include "core/mesh_view.h"
#include "io/mesh_attributes.h"

namespace fq::py {

namespace pyb = pybind11;

/// "vertices" (float32 (n, 3)) and "faces" (int64 (m, 3)), and what the attributes hold of
/// "colors" (float32 (n, 3|4) in [0, 1]), "normals" (n, 3), "uvs" (n, 2), "corner_uvs"
/// (m, 3, 2), "corner_normals" (m, 3, 3) and "labels" (uint32 (n,)).
pyb::dict mesh_dict(const Mesh& mesh, const io::MeshAttributes& attributes);

/// What of `attributes` a Mesh cannot carry (other vertex and face properties, materials),
/// one phrase a group, after what the reader itself could not keep.
std::vector<std::string> not_carried(const io::MeshAttributes& attributes);

/// The attributes of the optional arrays of `arrays` (keys of mesh_dict but vertices, faces
/// and labels; None or absent: not written). Colours are written as uchar 0..255. ValueError
/// naming the key for a wrong shape.
io::MeshAttributes attributes_of(const pyb::dict& arrays, size_t num_vertices, size_t num_triangles);

}  // namespace fq::py
