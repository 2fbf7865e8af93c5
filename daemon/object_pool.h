// A small thread-safe free list of reusable buffers (the engines' FrameResults, whose vectors
// the engines reuse), so that a steady stream of frames of similar size stops allocating
// after the first few frames. Only worth it for a T whose user keeps its capacity.
#pragma once

#include <cstddef>
#include <mutex>
#include <vector>

namespace fq::daemon {

template <class T>
class ObjectPool {
 public:
  explicit ObjectPool(size_t max_kept = 8) : max_kept_(max_kept) {}

  /// A previously released object (its capacity kept), or a new one.
  T acquire() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (free_.empty()) return T{};
    T t = std::move(free_.back());
    free_.pop_back();
    return t;
  }

  /// Gives an object back for reuse; dropped when the pool already keeps max_kept.
  void release(T&& t) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (free_.size() < max_kept_) free_.push_back(std::move(t));
  }

 private:
  std::mutex mutex_;
  std::vector<T> free_;
  size_t max_kept_;
};

}  // namespace fq::daemon
