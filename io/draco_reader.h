// Readers for .drc, .obj and .stl through Draco (internal to fq_io; use read_mesh).
#pragma once

#include <string>
#include <vector>

#include "common/status.h"
#include "core/mesh_view.h"
#include "io/mesh_attributes.h"

namespace fq::io {

/// Whole file into `bytes`; a status naming the file when it cannot be read.
Status read_file_bytes(const std::string& path, std::vector<char>& bytes);

/// Draco bitstream: a triangle mesh (a Draco point cloud is "not a triangle mesh"). With
/// `attributes`, its NORMAL, COLOR and TEX_COORD attributes and fq's labels become vertex
/// properties (nx, ny, nz; red, green, blue[, alpha]; u, v; label); others are named in
/// attributes->dropped.
Status read_drc(const std::string& path, Mesh& out, MeshAttributes* attributes = nullptr);

/// OBJ or binary STL through draco::ReadMeshFromFile (which fan-triangulates OBJ
/// polygons), welded to one vertex per distinct position value. A binary STL whose
/// triangle count disagrees with its size is rejected first: Draco would trust the
/// count and read far past the data. An OBJ's per-corner texture coordinates and normals and
/// its materials go to attributes->corner_uv, corner_normal and materials (when given).
Status read_obj_or_stl(const std::string& path, Mesh& out, MeshAttributes* attributes = nullptr);

/// An STL file that starts with "solid" and whose size is not that of the binary STL its
/// header would announce (binary headers may start with "solid" too).
bool is_ascii_stl(const std::string& path);

}  // namespace fq::io
