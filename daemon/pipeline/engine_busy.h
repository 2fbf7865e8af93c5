// Time each engine spent on frames (fq_engine_busy_seconds_total on /metrics): its rate is
// the engine's utilisation, the first number to look at when results are late. Written by
// the engine workers, read by the metrics page; lock-free.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

namespace fq {
class Engine;
}

namespace fq::daemon {

class EngineBusy {
 public:
  /// Before the workers start: one counter per engine, in this order.
  void reset(const std::vector<const Engine*>& engines) {
    engines_ = engines;
    busy_ns_ = std::make_unique<std::atomic<uint64_t>[]>(engines.size());
    frames_ = std::make_unique<std::atomic<uint64_t>[]>(engines.size());
  }
  /// A frame's run on `engine` took `ns`.
  void add(const Engine* engine, uint64_t ns) {
    for (size_t i = 0; i < engines_.size(); ++i)
      if (engines_[i] == engine) {
        busy_ns_[i].fetch_add(ns, std::memory_order_relaxed);
        frames_[i].fetch_add(1, std::memory_order_relaxed);
      }
  }
  size_t size() const { return engines_.size(); }
  double seconds(size_t i) const {
    return static_cast<double>(busy_ns_[i].load(std::memory_order_relaxed)) * 1e-9;
  }
  uint64_t frames(size_t i) const { return frames_[i].load(std::memory_order_relaxed); }

 private:
  std::vector<const Engine*> engines_;
  std::unique_ptr<std::atomic<uint64_t>[]> busy_ns_, frames_;
};

}  // namespace fq::daemon
