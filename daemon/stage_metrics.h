// Latency percentiles per stage over a sliding window of recent frames.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "common/sample_stats.h"
#include "daemon/latency_histogram.h"

namespace fq::daemon {

struct Percentiles {
  double p50_ms = 0, p95_ms = 0, p99_ms = 0;
  uint64_t count = 0;  ///< samples ever recorded (the percentiles cover the last kWindow)
};

/// The last kWindow samples of one quantity.
class SampleWindow {
 public:
  static constexpr size_t kWindow = 2048;
  void add(double ms);
  Percentiles summary() const;

 private:
  std::vector<double> ring_;
  size_t next_ = 0;
  uint64_t count_ = 0;
};

/// Windows by stage name ("decode", "engine", "engine.<pass>", "encode", "receive_to_publish"...).
class StageMetrics {
 public:
  void add(const std::string& stage, double ms) {
    stages_[stage].add(ms);
    histograms_[stage].add(ms);
  }
  std::map<std::string, Percentiles> summary() const;
  /// Every sample ever recorded, by stage (for /metrics).
  const std::map<std::string, LatencyHistogram>& histograms() const { return histograms_; }

 private:
  std::map<std::string, SampleWindow> stages_;
  std::map<std::string, LatencyHistogram> histograms_;
};

}  // namespace fq::daemon
