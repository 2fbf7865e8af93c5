// A small thread-safe free list of reusable buffers (the engines' FrameResults, whose vectors
// the engines reuse), so that a steady stream of frames of similar size stops allocating
// after the first few frames, and memory that returns when the stream changes: an object
// whose capacity is far above what its last frame used is freed instead of kept (a small
// frame after a huge one), and trim() frees everything kept once the pool has been idle.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <mutex>
#include <vector>

namespace fq::daemon {

template <class T>
class ObjectPool {
 public:
  /// Bytes an object holds (capacity) and uses (size); both 0 when not given.
  using Bytes = std::function<size_t(const T&)>;

  explicit ObjectPool(size_t max_kept = 8, Bytes capacity = {}, Bytes used = {})
      : max_kept_(max_kept), capacity_(std::move(capacity)), used_(std::move(used)) {}

  /// A previously released object (its capacity kept), or a new one.
  T acquire(int64_t now_ns = 0) {
    std::lock_guard<std::mutex> lock(mutex_);
    last_use_ns_ = now_ns;
    if (free_.empty()) return T{};
    T t = std::move(free_.back());
    free_.pop_back();
    return t;
  }

  /// Gives an object back for reuse; dropped when the pool already keeps max_kept, or when
  /// it holds more than 4x (and 1 MiB more than) what it used.
  void release(T&& t) {
    if (capacity_ && used_) {
      const size_t cap = capacity_(t), use = used_(t);
      if (cap > 4 * use && cap - use > (size_t(1) << 20)) {  // freed here
        oversized_freed_.fetch_add(1, std::memory_order_relaxed);
        return;
      }
    }
    std::lock_guard<std::mutex> lock(mutex_);
    if (free_.size() < max_kept_) free_.push_back(std::move(t));
  }

  /// Frees every kept object when nothing was acquired for `idle_ns`.
  void trim(int64_t now_ns, int64_t idle_ns) {
    std::vector<T> gone;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (now_ns - last_use_ns_ < idle_ns) return;
      gone.swap(free_);
    }
  }

  /// Objects freed by release() because they held far more than they used: memory that a
  /// huge frame took and a smaller one gave back (the daemon returns free pages after one).
  uint64_t oversized_freed() const { return oversized_freed_.load(std::memory_order_relaxed); }

  size_t kept() {
    std::lock_guard<std::mutex> lock(mutex_);
    return free_.size();
  }

 private:
  std::mutex mutex_;
  std::vector<T> free_;
  size_t max_kept_;
  Bytes capacity_, used_;
  int64_t last_use_ns_ = 0;
  std::atomic<uint64_t> oversized_freed_{0};
};

}  // namespace fq::daemon
