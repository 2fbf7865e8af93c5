// Vertex -> incident triangles (CSR) of a triangle list, by counting sort: each vertex's
// triangles in increasing order, so per-vertex sums over them are reproducible.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace fq {

/// `offsets` (n + 1 entries) and `faces` (3 per triangle) of the m triangles `tris` over n
/// vertices; vertex v's triangles are faces[offsets[v] .. offsets[v + 1]).
void build_vertex_faces(const uint32_t* tris, size_t m, uint32_t n, std::vector<uint32_t>& offsets,
                        std::vector<uint32_t>& faces);

}  // namespace fq
