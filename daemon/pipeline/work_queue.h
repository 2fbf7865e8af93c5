// A blocking FIFO between pipeline stages, optionally bounded: push() waits while the queue
// holds `capacity` items, so a slow stage holds back the one before it (backpressure)
// instead of letting a queue, and the latency, grow. close() wakes every waiting producer and
// consumer; items already queued are still handed out, so closing drains the pipeline.
#pragma once

#include <chrono>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <optional>

namespace fq::daemon {

template <class T>
class WorkQueue {
 public:
  /// capacity 0: unbounded.
  explicit WorkQueue(size_t capacity = 0) : capacity_(capacity) {}

  /// Sets the bound (before use).
  void set_capacity(size_t capacity) { capacity_ = capacity; }

  /// Waits for room, then queues; false (and `item` dropped) when the queue is closed.
  bool push(T item) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      room_.wait(lock, [&] { return closed_ || capacity_ == 0 || items_.size() < capacity_; });
      if (closed_) return false;
      items_.push_back(std::move(item));
    }
    ready_.notify_one();
    return true;
  }

  /// Blocks until an item is available; nothing once the queue is closed and empty.
  std::optional<T> pop() {
    std::unique_lock<std::mutex> lock(mutex_);
    ready_.wait(lock, [&] { return closed_ || !items_.empty(); });
    return take_front(lock);
  }

  /// pop() that gives up after `wait`: nothing then too, with `timed_out` set (so the
  /// caller can do periodic work); false when the queue is closed and empty.
  std::optional<T> pop_for(std::chrono::milliseconds wait, bool& timed_out) {
    std::unique_lock<std::mutex> lock(mutex_);
    timed_out = !ready_.wait_for(lock, wait, [&] { return closed_ || !items_.empty(); });
    return take_front(lock);
  }

  void close() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      closed_ = true;
    }
    ready_.notify_all();
    room_.notify_all();
  }

  size_t size() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return items_.size();
  }

 private:
  std::optional<T> take_front(std::unique_lock<std::mutex>& lock) {
    if (items_.empty()) return std::nullopt;
    T item = std::move(items_.front());
    items_.pop_front();
    lock.unlock();
    room_.notify_one();
    return item;
  }

  mutable std::mutex mutex_;
  std::condition_variable ready_, room_;
  std::deque<T> items_;
  size_t capacity_ = 0;
  bool closed_ = false;
};

}  // namespace fq::daemon
