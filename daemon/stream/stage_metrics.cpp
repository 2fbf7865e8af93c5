#include "daemon/stream/stage_metrics.h"

#include <cstddef>

namespace fq::daemon {

void SampleWindow::add(double ms) {
  if (ring_.size() < kWindow)
    ring_.push_back(ms);
  else
    ring_[next_] = ms;
  next_ = (next_ + 1) % kWindow;
  ++count_;
}

namespace {

Percentiles summarise(const std::vector<double>& samples, uint64_t count) {
  return {percentile(samples, 0.50), percentile(samples, 0.95), percentile(samples, 0.99), count};
}

}  // namespace

Percentiles SampleWindow::summary() const { return summarise(ring_, count_); }

std::map<std::string, Percentiles> SampleCopy::summary() const {
  std::map<std::string, Percentiles> out;
  for (const Stage& st : stages)
    out[st.name] = summarise(std::vector<double>(samples.begin() + static_cast<std::ptrdiff_t>(st.begin),
                                                 samples.begin() + static_cast<std::ptrdiff_t>(st.end)),
                             st.count);
  return out;
}

void StageMetrics::copy_samples(SampleCopy& out) const {
  out.stages.clear();
  out.samples.clear();
  for (const auto& [name, w] : stages_) {
    const size_t begin = out.samples.size();
    w.copy_to(out.samples);
    out.stages.push_back({name, begin, out.samples.size(), w.count()});
  }
}

std::map<std::string, Percentiles> StageMetrics::summary() const {
  std::map<std::string, Percentiles> out;
  for (const auto& [name, w] : stages_) out[name] = w.summary();
  return out;
}

}  // namespace fq::daemon
