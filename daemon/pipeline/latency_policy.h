// The latency policy: one waiting slot per stream between decode and the engines.
// A newer frame replaces a waiting older one (superseded); a frame already older than its
// stream's budget when a worker is free is dropped (stale). Every frame that leaves the
// slots gets a per-stream ticket so results publish in arrival order even with several
// engines. Thread-safe. A stream's slot and ticket counter live in its Stream (stream.h),
// under this object's lock; only the streams with a frame waiting are listed here.
//
// Order by engine time. Each stream's recent engine time (seconds of engine and cluster-id
// tracking, decayed with time constant kShareWindowS, kept in its slot) is its usage; a free
// engine takes the waiting stream of least usage, so a stream of light frames goes before one
// of heavy frames.
//
// Preemption, a last resort. Engines do not interleave frames, so a frame that runs for seconds
// holds its engine while the other streams' frames wait. A frame on an engine is stopped (error
// result, counted `preempted`, not `errors`) only when all of these hold: no engine is free; the
// streams running and waiting ask for more engine time than the engines have (a stream's demand:
// its frame cost over its frame interval), and the running stream asks for more than the waiting
// one; a waiting frame of that stream would miss its own budget if it waited for the running
// frame to end (its stream's frame cost included), and can still meet it if the engine is given
// up then; the running frame cannot meet its own budget (it is past it, or its stream's frames
// cost more than it has left); the frame has run kSliceS; and its stream was not preempted since
// its last frame that ran to its end (guaranteed progress: after a preemption the stream's next
// frame on an engine is never stopped for another stream). So a stream of tiny frames never
// stops a heavy stream while the engines have room for both (a 1 fps stream of 0.6 s frames
// beside 162-vertex frames at 5 fps), and a frame within its own budget is never stopped. A
// frame's cost is its stream's moving average of engine time over frames that ran to their end
// (the longest preempted run when larger); its interval, the moving average of the time between
// its frames' receipt. A stream with either unknown asks for nothing yet, so its first frame
// on an engine is not stopped.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "core/cancel_token.h"
#include "daemon/stream/frame_job.h"
#include "daemon/stream/stream.h"

namespace fq::daemon {

/// True when a frame received at `receive_ns` is older than `budget_ms` at `now_ns`.
inline bool is_stale(int64_t receive_ns, int64_t now_ns, double budget_ms) {
  return ms_between(receive_ns, now_ns) > budget_ms;
}

class FrameSlots {
 public:
  /// Puts a decoded frame (one with a stream) in its stream's slot. Returns the frame that
  /// lost: the older frame it replaced, or the frame itself when a newer one of its stream is
  /// already waiting or taken (decode finished out of order); null when nothing was replaced.
  FramePtr offer(FramePtr frame);

  /// Blocks until a frame is waiting, then hands one out to the calling worker in `out`,
  /// ticketed: the waiting stream of least recent engine time first (the stream served least
  /// recently among equals, then the oldest frame); frames found stale on the way are moved to
  /// `stale` (and `out` stays null when nothing fresh is left). False once closed and empty.
  /// With `wait`, also returns (true, `out` null) after waiting that long for a frame. With
  /// `yield`, the frame's run is registered until finish(): the slots set `yield` when the run
  /// should give its engine up (see above); the engine's token watches it.
  bool take(FramePtr& out, std::vector<FramePtr>& stale,
            std::chrono::milliseconds wait = std::chrono::milliseconds::max(), YieldRequest* yield = nullptr);

  /// The run of `yield` (taken with it) is over after `seconds` on its engine: charged to its
  /// stream, unregistered. `preempted`: the run was stopped by its yield request, which is
  /// counted on the stream the request was for (`preempted_others`).
  void finish(YieldRequest* yield, double seconds, bool preempted = false);

  /// Engines that take from the slots (the engine time there is to ask for).
  void set_engines(int engines);

  /// Charges `seconds` of other work of a frame (cluster-id tracking) to its stream.
  void charge(Stream& stream, double seconds);

  static constexpr double kShareWindowS = 6.0;
  static constexpr double kSliceS = 0.1;

  /// Wakes every waiting worker; waiting frames are still handed out.
  void close();

  /// Frames waiting in the slots now (fq_queue_depth{queue="slots"}).
  size_t waiting() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return waiting_.size();
  }

 private:
  /// A frame on an engine, taken with a YieldRequest; `stream` is the frame's.
  struct Run {
    StreamPtr stream;
    YieldRequest* yield;
    int64_t start_ns;     ///< steady clock
    int64_t deadline_ns;  ///< the end of the frame's budget, steady clock
    /// The waiting stream its last yield request was for: a stopped run is counted there
    /// (`preempted_others`). Kept when the request is withdrawn, since a run that saw it due
    /// still stops. Weak: a Run never keeps a stream alive, nor ends one under the lock.
    std::weak_ptr<Stream> for_stream;
  };

  /// The slot's usage decayed to `now_ns` (steady clock).
  static double usage_at(SlotState& s, int64_t now_ns);
  /// Sets or withdraws the yield requests of the runs (see above). Under mutex_.
  void review_runs(int64_t now_ns);
  /// Engine seconds per second the stream asks for (see above); 0 while unknown.
  static double demand(const SlotState& s);
  /// When `r` may be stopped for the waiting stream `w` (steady clock), or -1 when never.
  static int64_t stop_time(const Run& r, const Stream& w, int64_t now_ns, int64_t wall_to_steady_ns);

  mutable std::mutex mutex_;
  std::condition_variable ready_;
  /// The streams whose slot holds a frame; that frame keeps its stream alive.
  std::vector<Stream*> waiting_;
  std::vector<Run> runs_;
  uint64_t served_ = 0;
  int engines_ = 1;
  int idle_takers_ = 0;  ///< workers blocked in take()
  bool closed_ = false;
};

}  // namespace fq::daemon
