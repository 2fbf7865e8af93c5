// Temporal filtering in fqd (kernels/temporal.h): each stream whose "qf+" has temporal > 0 keeps
// its last result in its Stream (stream.h: TemporalTrack), which the engine pulls the stream's
// next frame towards. It goes with the stream (expiry); a scene cut restarts it inside the
// engine. Streams do not wait on each other: each history has its stream's lock.
#pragma once

#include <cstdint>
#include <mutex>

#include "daemon/stream/stream.h"
#include "kernels/engine.h"

namespace fq::daemon {

/// Whether `params` filter across frames (qf+ with temporal > 0).
inline bool uses_history(const Params& params) {
  return params.filter && params.filtering.method == FilterMethod::kQuadricRefined && params.filtering.temporal > 0.f;
}

/// Runs `run` (the frame's engine call) with the stream's history set on `engine` when the
/// frame's parameters ask for temporal filtering. Frames of one stream may reach several
/// engines at once: they take turns, and a frame that arrived before the one the history
/// holds (it finished after a newer one) runs alone, leaving the history to the newer frame.
/// A frame whose parameters do not ask for it forgets the stream's history.
template <class Run>
auto with_history(Stream& stream, uint64_t arrival, const Params& params, Engine& engine, Run&& run) {
  TemporalTrack& t = stream.temporal;
  if (!uses_history(params)) {
    {
      const std::lock_guard<std::mutex> lock(t.mutex);
      if (!t.history.empty()) {
        t.history = TemporalHistory{};
        t.last_arrival = 0;
      }
    }
    return run();
  }
  const std::lock_guard<std::mutex> lock(t.mutex);
  const bool in_order = t.history.empty() || arrival > t.last_arrival;
  engine.set_history(in_order ? &t.history : nullptr);
  auto result = run();
  engine.set_history(nullptr);
  if (in_order && !t.history.empty()) t.last_arrival = arrival;
  return result;
}

}  // namespace fq::daemon
