// Temporal filtering in fqd (kernels/temporal.h): each stream whose "qf+" has temporal > 0 keeps
// its last result in its Stream (stream.h: TemporalTrack), which the engine pulls the stream's
// next frame towards. It goes with the stream (expiry); a scene cut restarts it inside the
// engine. Streams do not wait on each other: each history has its stream's lock. Its bytes are
// charged to the host memory budget (memory_account.h), which may drop it (counted
// `memory_resets`): the next frame then runs alone, as after a restart.
#pragma once

#include <cstdint>
#include <mutex>

#include "daemon/stream/stream.h"
#include "kernels/engine.h"

namespace fq::daemon {

/// Whether `params` filter across frames (qf+ with temporal > 0).
inline bool uses_history(const Params& params) {
  return params.filter && params.filtering.method == FilterMethod::kQuadricRefined &&
         params.filtering.temporal > 0.f;
}

/// Bytes of the search index over a history's vertices (kernels/frame_matcher.h: the copy of the
/// points, 12 bytes, the points in cell order, 16, and their ranks, 4).
inline constexpr uint64_t kHistoryIndexBytesPerVertex = 32;

/// What a history holds in host memory: its vectors' capacity, track A's (its last averaged
/// input and its connectivity's tables, IdTrack::bytes) and, once built, its index.
inline uint64_t history_bytes(const TemporalHistory& h) {
  uint64_t b =
      sizeof(float) * (h.positions.capacity() + h.normals.capacity() + h.motion.capacity()) + h.ids.bytes();
  if (h.index_stamp != 0) b += kHistoryIndexBytesPerVertex * (h.positions.size() / 3);
  return b;
}

/// Drops the stream's history and its charge (with t.mutex held): its next frame runs alone.
inline void drop_history(TemporalTrack& t) {
  t.history = TemporalHistory{};
  t.last_arrival = 0;
  t.charge.release();
}

/// Charges the history a frame left (with t.mutex held), making room by the budget's order;
/// a history that does not fit is dropped and counted.
inline void charge_history(Stream& stream, TemporalTrack& t) {
  stream.kept_ns.store(wall_ns(), std::memory_order_relaxed);
  if (t.charge.set(stream.memory, MemoryKind::kHistory, history_bytes(t.history), Shed::kHistories, &stream))
    return;
  drop_history(t);
  stream.count(&StreamCounters::memory_resets);
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
      if (!t.history.empty() || t.charge.bytes() > 0) drop_history(t);
    }
    return run();
  }
  const std::lock_guard<std::mutex> lock(t.mutex);
  const bool in_order = t.history.empty() || arrival > t.last_arrival;
  engine.set_history(in_order ? &t.history : nullptr);
  auto result = run();
  engine.set_history(nullptr);
  if (in_order && !t.history.empty()) t.last_arrival = arrival;
  if (in_order) charge_history(stream, t);
  return result;
}

}  // namespace fq::daemon
