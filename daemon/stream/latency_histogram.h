// Cumulative latency histogram with fixed buckets, as Prometheus histograms want them: unlike
// the percentile windows it never forgets, so rates and quantiles over any range can be
// computed by the monitoring system from successive scrapes.
#pragma once

#include <array>
#include <cstdint>

namespace fq::daemon {

class LatencyHistogram {
 public:
  /// Upper bounds in milliseconds (the "le" labels, in seconds, divide by 1000); a frame
  /// budget of 33 or 100 ms falls between buckets so that "within budget" reads off one.
  static constexpr std::array<double, 14> kBoundsMs = {1,   2.5, 5,   10,   20,   33,   50,
                                                       100, 250, 500, 1000, 2500, 5000, 10000};

  void add(double ms) {
    for (size_t i = 0; i < kBoundsMs.size(); ++i)
      if (ms <= kBoundsMs[i]) ++buckets_[i];
    ++count_;
    sum_ms_ += ms;
  }
  /// Adds another histogram's samples (the /metrics aggregate of streams without own series).
  void add(const LatencyHistogram& o) {
    for (size_t i = 0; i < buckets_.size(); ++i) buckets_[i] += o.buckets_[i];
    count_ += o.count_;
    sum_ms_ += o.sum_ms_;
  }
  /// The samples added since `base`, an earlier copy of this histogram.
  LatencyHistogram since(const LatencyHistogram& base) const {
    LatencyHistogram d = *this;
    for (size_t i = 0; i < buckets_.size(); ++i) d.buckets_[i] -= base.buckets_[i];
    d.count_ -= base.count_;
    d.sum_ms_ -= base.sum_ms_;
    return d;
  }
  /// Samples at or below kBoundsMs[i] (cumulative).
  uint64_t bucket(size_t i) const { return buckets_[i]; }
  uint64_t count() const { return count_; }
  double sum_ms() const { return sum_ms_; }

 private:
  std::array<uint64_t, kBoundsMs.size()> buckets_{};
  uint64_t count_ = 0;
  double sum_ms_ = 0;
};

}  // namespace fq::daemon
