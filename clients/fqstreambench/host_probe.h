// How quiet the host was while a benchmark ran. A thread asks to sleep 1 ms over and over and
// records how late each wake-up comes, and /proc/stat gives the share of CPU time the
// hypervisor took (steal). A latency tail measured on a host whose threads wake 10 ms late is
// the host's, not fqd's: the report carries both so runs on different hosts can be told apart
// (docs/BENCHMARKS.md, "Single streams with the producer's frames in chunks").
#pragma once

#include <atomic>
#include <cstdint>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace fq::bench {

struct HostQuiet {
  uint64_t wakeups = 0;
  double late_p50_ms = 0, late_p99_ms = 0, late_max_ms = 0;  ///< after the 1 ms asked for
  uint64_t late_over_5ms = 0;
  double steal_share = -1;  ///< of all CPU time over the run; -1 where /proc/stat is unreadable
};

/// CPU time counters of /proc/stat's first line (all CPUs), in clock ticks.
struct CpuTicks {
  uint64_t total = 0, steal = 0;
};
/// Parses a "cpu  user nice system idle iowait irq softirq steal ..." line.
std::optional<CpuTicks> parse_cpu_line(const std::string& line);

class HostProbe {
 public:
  HostProbe() = default;
  HostProbe(const HostProbe&) = delete;
  HostProbe& operator=(const HostProbe&) = delete;
  ~HostProbe();
  void start();
  /// Stops the thread and summarizes what it saw since start().
  HostQuiet stop();

 private:
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::vector<double> late_ms_;
  std::optional<CpuTicks> ticks0_;
};

}  // namespace fq::bench
