// Draco payloads as any producer (not fq's codec) would make them, for the bad-input tests:
// plain meshes without fq_vid (raw float positions, so NaN survives) and point clouds.
#pragma once

#include <string>

#include "core/mesh_view.h"

namespace fq::test {

/// A single-chunk Draco mesh of `mesh` with unquantized positions (sequential encoding).
std::string draco_plain_mesh(const Mesh& mesh);

/// A Draco point cloud of the mesh's vertices.
std::string draco_point_cloud(const Mesh& mesh);

}  // namespace fq::test
