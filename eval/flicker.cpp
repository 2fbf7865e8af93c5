#include "eval/flicker.h"

#include <algorithm>
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

FlickerParts flicker_parts(const float* r, const float* r_prev, const float* c, const float* c_prev,
                           const double* normals, uint32_t n, double mean_edge) {
  if (n == 0 || !(mean_edge > 0.0)) return {};
  double total = 0.0, along = 0.0;
  for (size_t v = 0; v < n; ++v) {
    double d[3], dn = 0.0;
    for (size_t k = 0; k < 3; ++k) {
      const size_t i = 3 * v + k;
      d[k] = (double(r[i]) - r_prev[i]) - (double(c[i]) - c_prev[i]);
      total += d[k] * d[k];
      dn += d[k] * normals[i];
    }
    along += dn * dn;
  }
  const double tangential = std::max(total - along, 0.0);  // rounding may take it below 0
  return {std::sqrt(total / n) / mean_edge, std::sqrt(along / n) / mean_edge,
          std::sqrt(tangential / n) / mean_edge};
}

}  // namespace fq
