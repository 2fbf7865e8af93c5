// fqd's own process, as Prometheus' client libraries export it for every process they run in
// (process_cpu_seconds_total, process_resident_memory_bytes, ...): read from /proc/self, the
// way those libraries do. There is no Prometheus client library for C++ in Debian, and these
// are a few numbers from two files.
#pragma once

#include <cstdint>
#include <string>

namespace fq::daemon {

struct ProcessStats {
  double cpu_seconds = 0;         ///< user + system CPU time
  uint64_t resident_bytes = 0;    ///< resident set size
  uint64_t virtual_bytes = 0;     ///< virtual memory size
  double start_time_seconds = 0;  ///< since the Unix epoch
  uint64_t open_fds = 0;
  uint64_t max_fds = 0;  ///< RLIMIT_NOFILE's soft limit
  uint64_t threads = 0;
  bool ok = false;  ///< false when /proc/self/stat could not be read
};

/// The calling process's statistics (not ok outside Linux or without /proc).
ProcessStats read_process_stats();

/// Parses the text of /proc/PID/stat; `ticks` per second, `page` bytes, `boot_time` from
/// /proc/stat's btime. Fields not found stay 0 and `ok` false.
ProcessStats parse_proc_stat(const std::string& stat, long ticks, long page, double boot_time);

/// The process_* families in the Prometheus text format (nothing when !s.ok).
std::string process_metrics_text(const ProcessStats& s);

}  // namespace fq::daemon
