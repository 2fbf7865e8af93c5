// Cooperative cancellation of one engine run: a deadline and/or a stop flag that the engines
// check between passes (and the CPU engine at the start of every chunk of its parallel
// loops, see parallel_for.h). Nothing is interrupted mid-item, so a frame that finishes is
// computed exactly as without a token; a frame that is stopped returns kCancelled and its
// outputs are left unspecified.
#pragma once

#include <atomic>
#include <chrono>

#include "common/non_copyable.h"
#include "common/status.h"

namespace fq {

/// A scheduler's request that a run give its engine up: once `requested` is set, the run's
/// token expires at `after_ns` (steady clock). Set from another thread while the run goes on.
struct YieldRequest {
  std::atomic<bool> requested{false};
  std::atomic<int64_t> after_ns{0};
};

class CancelToken {
 public:
  using Clock = std::chrono::steady_clock;

  /// Expired once `*stop` is true (may be null), once `deadline` has passed, or once `*yield`
  /// (may be null) is requested and due.
  explicit CancelToken(const std::atomic<bool>* stop = nullptr,
                       Clock::time_point deadline = Clock::time_point::max(),
                       const YieldRequest* yield = nullptr)
      : stop_(stop), deadline_(deadline), yield_(yield) {}

  bool stopped() const { return stop_ != nullptr && stop_->load(std::memory_order_relaxed); }
  bool past_deadline() const { return deadline_ != Clock::time_point::max() && Clock::now() >= deadline_; }
  /// Latched: a request withdrawn after it was seen due (the stream it was for got another
  /// engine) still stops the run, whose loops may already have skipped work.
  bool yield_due() const {
    if (yielded_.load(std::memory_order_relaxed)) return true;
    if (yield_ == nullptr || !yield_->requested.load(std::memory_order_relaxed) ||
        Clock::now().time_since_epoch().count() < yield_->after_ns.load(std::memory_order_relaxed))
      return false;
    yielded_.store(true, std::memory_order_relaxed);
    return true;
  }
  /// Monotonic: once true it stays true, so a run that checks after its last loop and finds
  /// it false skipped no work.
  bool expired() const { return stopped() || past_deadline() || yield_due(); }
  /// Ok, or kCancelled naming the cause.
  Status check() const {
    if (stopped()) return {StatusCode::kCancelled, "cancelled"};
    if (yield_due()) return {StatusCode::kCancelled, "preempted"};
    if (past_deadline()) return {StatusCode::kCancelled, "time limit exceeded"};
    return {};
  }

 private:
  const std::atomic<bool>* stop_;
  Clock::time_point deadline_;
  const YieldRequest* yield_;
  mutable std::atomic<bool> yielded_{false};
};

/// The token of the engine run on the calling thread (null: none). parallel_for reads it on
/// the calling thread and hands it to the pool threads that help with the loop.
const CancelToken* current_cancel_token();

/// Makes `token` the calling thread's current token for this object's lifetime (nests).
class CancelScope : NonCopyable {
 public:
  explicit CancelScope(const CancelToken* token);
  ~CancelScope();

 private:
  const CancelToken* previous_;
};

}  // namespace fq
