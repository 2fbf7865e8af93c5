#include "daemon/stage_metrics.h"

namespace fq::daemon {

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
