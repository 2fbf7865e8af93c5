// PLY reading that keeps the file's vertices (internal to fq_io; use read_mesh).
#pragma once

#include <string>

#include "common/status.h"
#include "core/mesh_view.h"
#include "io/mesh_attributes.h"

namespace fq::io {

/// Reads a PLY with Draco's PlyReader (ASCII or binary little-endian). We do not use
/// draco::ReadMeshFromFile for PLY because its PlyDecoder deduplicates attribute values
/// and point ids, which merges coincident vertices (dragon.ply: 435,545 -> 383,559) and
/// reorders them; filtered output must keep the input's vertex count and order.
/// Polygons are split into triangles (the fan of each face, whose face properties each
/// triangle takes); a file without a face element reads as zero triangles. With `attributes`, also every
/// other vertex and face property (colours, normals, texture coordinates, scalars, lists); other elements are
/// named in attributes->dropped.
Status read_ply(const std::string& path, Mesh& out, MeshAttributes* attributes = nullptr);

}  // namespace fq::io
