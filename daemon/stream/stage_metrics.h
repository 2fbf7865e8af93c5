// Latency percentiles per stage over a sliding window of recent frames.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "common/sample_stats.h"
#include "daemon/stream/latency_histogram.h"

namespace fq::daemon {

struct Percentiles {
  double p50_ms = 0, p95_ms = 0, p99_ms = 0;
  uint64_t count = 0;  ///< samples ever recorded (the percentiles cover the last kWindow)
};

/// The samples of a StageMetrics copied out in one buffer, so that the percentiles are
/// computed without the lock that guards the metrics (StreamRegistry::snapshot).
struct SampleCopy {
  struct Stage {
    std::string name;
    size_t begin = 0, end = 0;  ///< its samples in `samples`
    uint64_t count = 0;
  };
  std::vector<Stage> stages;
  std::vector<double> samples;  ///< reused from copy to copy
  std::map<std::string, Percentiles> summary() const;
};

/// The last kWindow samples of one quantity.
class SampleWindow {
 public:
  static constexpr size_t kWindow = 2048;
  void add(double ms);
  Percentiles summary() const;
  /// Appends its samples (in no particular order) to `out`.
  void copy_to(std::vector<double>& out) const { out.insert(out.end(), ring_.begin(), ring_.end()); }
  uint64_t count() const { return count_; }

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
  /// Replaces `out` with the samples of every stage (a memory copy; summary() of the copy is
  /// this object's summary()).
  void copy_samples(SampleCopy& out) const;
  /// Every sample ever recorded, by stage (for /metrics).
  const std::map<std::string, LatencyHistogram>& histograms() const { return histograms_; }

 private:
  std::map<std::string, SampleWindow> stages_;
  std::map<std::string, LatencyHistogram> histograms_;
};

}  // namespace fq::daemon
