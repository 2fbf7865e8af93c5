// Binary glTF (.glb) through assimp (internal to fq_io; use write_mesh). Assimp is
// Debian's maintained importer/exporter for these formats; tinygltf, the other candidate, is
// glTF-only, so it could not also give us ASCII STL in (assimp_io.h).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "common/status.h"
#include "core/mesh_view.h"
#include "io/mesh_attributes.h"

namespace fq::io {

/// Binary glTF: positions, triangles, and what glTF holds of `attributes`: normals and
/// texture coordinates (per corner when the input has them: a vertex is split where its
/// corners differ; else nx, ny, nz and u, v / s, t / texture_u, texture_v; normals always,
/// the area-weighted vertex normals of `mesh` when `attributes` has none), vertex colours
/// (red, green, blue[, alpha]; with `colour_clusters` the cluster colours), and one
/// primitive per material of an OBJ's library (name, diffuse colour and texture, the
/// texture by its path from the output's folder). Everything else (labels, scalars, face
/// properties) is named in `dropped`, one phrase a group.
Status write_glb(const std::string& path, const MeshView& mesh, const uint32_t* labels,
                 const MeshAttributes* attributes, bool colour_clusters, std::vector<std::string>& dropped);

}  // namespace fq::io
