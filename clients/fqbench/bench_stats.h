// Median and spread of repeated timings, and the per-pass collection of a run of frames.
#pragma once

#include <functional>
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

/// CPU time of the whole process (all threads), in ms: the work done, less sensitive than wall
/// time to other jobs on a shared machine.
double cpu_ms();

/// Runs `step` (false: it failed, and so `ok` becomes false) and appends its wall and CPU ms
/// to `wall` and `cpu`.
void time_step(const std::function<bool()>& step, bool& ok, std::vector<double>& wall,
               std::vector<double>& cpu);

/// Host-side passes and transfers, which "device" leaves out.
bool is_host_or_transfer(const std::string& pass);

}  // namespace fq::bench
