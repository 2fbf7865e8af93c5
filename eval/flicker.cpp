#include "eval/flicker.h"

#include <cmath>

namespace fq {

double flicker(const float* r, const float* r_prev, const float* c, const float* c_prev, uint32_t n,
               double mean_edge) {
  if (n == 0 || !(mean_edge > 0.0)) return 0.0;
  double sum = 0.0;
  for (size_t i = 0; i < 3 * size_t(n); ++i) {
    const double d = (double(r[i]) - r_prev[i]) - (double(c[i]) - c_prev[i]);
    sum += d * d;
  }
  return std::sqrt(sum / n) / mean_edge;
}

}  // namespace fq
