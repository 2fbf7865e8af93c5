#include "common/sample_stats.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace fq {

double percentile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  const size_t rank = static_cast<size_t>(std::ceil(q * static_cast<double>(values.size())));
  const size_t k = std::min(values.size() - 1, rank > 0 ? rank - 1 : 0);
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k];
}

double median(std::vector<double> values) { return percentile(std::move(values), 0.5); }

}  // namespace fq
