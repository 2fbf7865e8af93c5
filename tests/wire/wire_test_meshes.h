// Meshes for the wire tests: made in code, or the shared real meshes (binary PLY).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "core/mesh_view.h"

namespace fq::test_wire {

/// nx x ny quads (two triangles each) on a bumpy height field: (nx+1)(ny+1) distinct positions.
Mesh make_bumpy_grid(int nx, int ny);

/// Every triangle of `m` with its own three vertices: coincident positions, distinct vertices.
Mesh make_soup(const Mesh& m);

/// The shared mesh `file_name` (env FQ_MESH_DIR, else the build-time folder), or nothing when
/// the file is missing. Reads the shared meshes' binary PLY form (float xyz, uchar/int faces).
std::optional<Mesh> load_shared_mesh(const std::string& file_name);

/// Triangles as a sorted list, each rotated so its smallest index comes first (orientation kept).
std::vector<std::array<uint32_t, 3>> triangle_set(const std::vector<uint32_t>& triangles);

}  // namespace fq::test_wire

namespace fq::test_wire {

/// `chunk` (a Draco mesh) with its declared face count replaced by `faces`: the shape of a
/// decode bomb, a few hundred bytes that ask the decoder for gigabytes.
std::string forge_face_count(const std::string& chunk, uint64_t faces);

}  // namespace fq::test_wire
