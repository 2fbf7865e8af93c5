// fqd's per-stream memory for temporal filtering (kernels/temporal.h): each stream whose "qf+"
// has temporal > 0 keeps its last result, which the engine pulls the stream's next frame
// towards. Forgotten with the stream (expiry); a scene cut restarts it inside the engine.
// Thread-safe; streams do not wait on each other.
#pragma once

#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "kernels/engine.h"

namespace fq::daemon {

class StreamHistories {
 public:
  /// Runs `run` (the frame's engine call) with the stream's history set on `engine` when the
  /// frame's parameters ask for temporal filtering. Frames of one stream may reach several
  /// engines at once: they take turns, and a frame that arrived before the one the history
  /// holds (it finished after a newer one) runs alone, leaving the history to the newer frame.
  /// A frame whose parameters do not ask for it forgets the stream's history.
  template <class Run>
  auto with_history(const std::string& stream_id, uint64_t arrival, const Params& params, Engine& engine, Run&& run);

  /// Forgets a stream (expired, or no longer filtered across frames).
  void forget(const std::string& stream_id);

 private:
  struct Slot {
    std::mutex mutex;
    TemporalHistory history;
    uint64_t last_arrival = 0;
  };
  std::shared_ptr<Slot> slot_of(const std::string& stream_id);

  std::mutex mutex_;
  std::map<std::string, std::shared_ptr<Slot>> slots_;
  /// slots_.size(), read without the lock: frames of streams without temporal filtering pass
  /// by without taking it while no stream has a history.
  std::atomic<size_t> count_{0};
};

/// Whether `params` filter across frames (qf+ with temporal > 0).
inline bool uses_history(const Params& params) {
  return params.filter && params.filtering.method == FilterMethod::kQuadricRefined && params.filtering.temporal > 0.f;
}

template <class Run>
auto StreamHistories::with_history(const std::string& stream_id, uint64_t arrival, const Params& params,
                                   Engine& engine, Run&& run) {
  if (!uses_history(params)) {
    if (count_.load(std::memory_order_relaxed) > 0) forget(stream_id);
    return run();
  }
  const std::shared_ptr<Slot> slot = slot_of(stream_id);
  const std::lock_guard<std::mutex> lock(slot->mutex);
  const bool in_order = slot->history.empty() || arrival > slot->last_arrival;
  engine.set_history(in_order ? &slot->history : nullptr);
  auto result = run();
  engine.set_history(nullptr);
  if (in_order && !slot->history.empty()) slot->last_arrival = arrival;
  return result;
}

}  // namespace fq::daemon
