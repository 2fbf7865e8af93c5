// A log line that any peer or any message can cause goes through a LogLimiter: at most
// `per_second` such lines a second are written, the rest are counted, and the next line written
// says how many were held back. One limiter per kind of line (refused frames, ZAP refusals,
// control changes, ...), so that junk traffic on one door cannot flood the log or hide the
// lines of another. Thread-safe.
#pragma once

#include <spdlog/spdlog.h>

#include <cstdint>
#include <mutex>
#include <string>
#include <utility>

namespace fq::daemon {

class LogLimiter {
 public:
  explicit LogLimiter(int per_second = 5) : per_second_(per_second) {}

  /// True when a line may be written at `now_ns` (steady clock); `suppressed` is then the number
  /// held back since the last one written.
  bool allow(int64_t now_ns, uint64_t& suppressed);
  /// allow() at the steady clock's now.
  bool allow_now(uint64_t& suppressed) { return allow(now_ns(), suppressed); }

  /// Writes the line at `level` when allowed, with " (N similar messages not logged)" appended
  /// when lines were held back.
  template <class... Args>
  void log(spdlog::level::level_enum level, fmt::format_string<Args...> format, Args&&... args) {
    uint64_t held_back = 0;
    if (!spdlog::should_log(level) || !allow_now(held_back)) return;
    std::string line = fmt::format(format, std::forward<Args>(args)...);
    if (held_back > 0) line += fmt::format(" ({} similar messages not logged)", held_back);
    spdlog::log(level, "{}", line);
  }

 private:
  static int64_t now_ns();

  const int per_second_;
  std::mutex mutex_;
  int64_t window_start_ns_ = 0;
  int in_window_ = 0;
  uint64_t suppressed_ = 0;
};

}  // namespace fq::daemon
