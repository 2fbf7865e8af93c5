#include "kernels/vertex_faces.h"

namespace fq {

void build_vertex_faces(const uint32_t* tris, size_t m, uint32_t n, std::vector<uint32_t>& offsets,
                        std::vector<uint32_t>& faces) {
  offsets.assign(size_t(n) + 1, 0);
  for (size_t i = 0; i < 3 * m; ++i) ++offsets[tris[i] + 1];
  for (uint32_t v = 0; v < n; ++v) offsets[v + 1] += offsets[v];
  faces.resize(3 * m);
  std::vector<uint32_t> cursor(offsets.begin(), offsets.end() - 1);
  for (size_t t = 0; t < m; ++t)
    for (int k = 0; k < 3; ++k) faces[cursor[tris[3 * t + k]]++] = static_cast<uint32_t>(t);
}

}  // namespace fq
