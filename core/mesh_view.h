// Non-owning view of a triangle mesh as the engines take it.
#pragma once

#include <cstdint>
#include <vector>

namespace fq {

struct MeshView {
  const float* positions = nullptr;  ///< 3 floats per vertex
  uint32_t num_vertices = 0;
  const uint32_t* triangles = nullptr;  ///< 3 indices per triangle
  uint32_t num_triangles = 0;
};

/// Owning mesh (what file readers and decoders produce).
struct Mesh {
  std::vector<float> positions;
  std::vector<uint32_t> triangles;

  uint32_t num_vertices() const { return static_cast<uint32_t>(positions.size() / 3); }
  uint32_t num_triangles() const { return static_cast<uint32_t>(triangles.size() / 3); }
  MeshView view() const { return {positions.data(), num_vertices(), triangles.data(), num_triangles()}; }
};

}  // namespace fq
