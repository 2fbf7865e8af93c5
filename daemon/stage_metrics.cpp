#include "daemon/stage_metrics.h"

#include <algorithm>
#include <cmath>

namespace fq::daemon {

double percentile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  // Nearest rank: the smallest value with at least q of the samples at or below it.
  const size_t rank = static_cast<size_t>(std::ceil(q * static_cast<double>(values.size())));
  const size_t k = std::min(values.size() - 1, rank > 0 ? rank - 1 : 0);
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k];
}

void SampleWindow::add(double ms) {
  if (ring_.size() < kWindow)
    ring_.push_back(ms);
  else
    ring_[next_] = ms;
  next_ = (next_ + 1) % kWindow;
  ++count_;
}

Percentiles SampleWindow::summary() const {
  return {percentile(ring_, 0.50), percentile(ring_, 0.95), percentile(ring_, 0.99), count_};
}

std::map<std::string, Percentiles> StageMetrics::summary() const {
  std::map<std::string, Percentiles> out;
  for (const auto& [name, w] : stages_) out[name] = w.summary();
  return out;
}

}  // namespace fq::daemon
