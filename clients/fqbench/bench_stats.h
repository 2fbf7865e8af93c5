// Median and spread of repeated timings, and the per-pass collection of a run of frames.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "kernels/engine.h"

namespace fq::bench {

struct Spread {
  double median = 0.0, p10 = 0.0, p90 = 0.0;
  int count = 0;
};

/// Median and 10th/90th percentiles (nearest rank, common/sample_stats.h) of `v`.
Spread spread_of(const std::vector<double>& v);

/// Timings of repeated frames, per pass name, in first-seen pass order.
class PassSamples {
 public:
  /// Adds one frame: each pass, plus "device" (every pass that is not a transfer or host
  /// work) and "frame" (the engine's whole reported time).
  void add(const FrameResult& r);
  const std::vector<std::string>& names() const { return names_; }
  Spread spread(const std::string& name) const;

 private:
  void push(const std::string& name, double ms);
  std::vector<std::string> names_;
  std::map<std::string, std::vector<double>> samples_;
};

/// Host-side passes and transfers, which "device" leaves out.
bool is_host_or_transfer(const std::string& pass);

}  // namespace fq::bench
