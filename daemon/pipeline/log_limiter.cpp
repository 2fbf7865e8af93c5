#include "daemon/pipeline/log_limiter.h"

#include <chrono>

namespace fq::daemon {

int64_t LogLimiter::now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

bool LogLimiter::allow(int64_t now_ns, uint64_t& suppressed) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (now_ns - window_start_ns_ >= 1'000'000'000) {
    window_start_ns_ = now_ns;
    in_window_ = 0;
  }
  if (in_window_ >= per_second_) {
    ++suppressed_;
    return false;
  }
  ++in_window_;
  suppressed = suppressed_;
  suppressed_ = 0;
  return true;
}

}  // namespace fq::daemon
