#include "eval/vertex_moves.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace fq {

VertexMoves vertex_moves(const float* before, const float* after, uint32_t n, double unit) {
  VertexMoves m;
  if (n == 0 || !(unit > 0.0)) return m;
  std::vector<double> d(n);
  double sum = 0.0;
  for (uint32_t i = 0; i < n; ++i) {
    double s = 0.0;
    for (int c = 0; c < 3; ++c) {
      const double x = double(after[3 * size_t(i) + c]) - before[3 * size_t(i) + c];
      s += x * x;
    }
    d[i] = std::sqrt(s) / unit;
    sum += d[i];
    m.max = std::max(m.max, d[i]);
  }
  m.mean = sum / n;
  // Nearest rank: the smallest value with at least 99 % of the vertices at or below it.
  const size_t rank = size_t(std::ceil(0.99 * n)) - 1;
  std::nth_element(d.begin(), d.begin() + rank, d.end());
  m.p99 = d[rank];
  return m;
}

}  // namespace fq
