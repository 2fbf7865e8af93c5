// Mesh formats through assimp (internal to fq_io; use read_mesh / write_mesh): ASCII
// STL in (Draco reads binary STL only), OBJ and binary glTF (.glb) out. Assimp is Debian's
// maintained importer/exporter for these formats; tinygltf, the other candidate, is
// glTF-only, so it could not also give us ASCII STL and OBJ.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "common/status.h"
#include "core/mesh_view.h"
#include "io/mesh_attributes.h"

namespace fq::io {

/// ASCII STL, welded like binary STL: one vertex per distinct position, in order of first use.
Status read_ascii_stl(const std::string& path, Mesh& out);

/// .obj (no material file) or .glb by extension: positions, triangles, and what the format
/// holds of `attributes`: normals (nx, ny, nz), texture coordinates (u, v / s, t /
/// texture_u, texture_v) and vertex colours (red, green, blue[, alpha]; glb only: OBJ has
/// no standard vertex colour). With `colour_clusters` the colours are the cluster colours.
/// Everything else (labels, scalars, face properties) is named in `dropped`.
Status write_with_assimp(const std::string& path, const MeshView& mesh, const uint32_t* labels,
                         const MeshAttributes* attributes, bool colour_clusters,
                         std::vector<std::string>& dropped);

}  // namespace fq::io
