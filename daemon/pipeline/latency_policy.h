// The latency policy: one waiting slot per stream between decode and the engines.
// A newer frame replaces a waiting older one (superseded); a frame already older than its
// stream's budget when a worker is free is dropped (stale). Every frame that leaves the
// slots gets a per-stream ticket so results publish in arrival order even with several
// engines. Thread-safe. A stream's slot and ticket counter live in its Stream (stream.h),
// under this object's lock; only the streams with a frame waiting are listed here.
//
// Fairness by engine time. Each stream's recent engine time (seconds of engine and cluster-id
// tracking, decayed with time constant kShareWindowS, kept in its slot) is its usage; a free engine takes the
// waiting stream of least usage. A stream's share is kShareWindowS x engines / active streams
// (those with a frame in the last kShareWindowS). Engines do not interleave frames, so without
// more a stream whose frames run for seconds would still hold the engine while a light stream's
// frames were superseded behind it (one waiting slot); so a frame on an engine is stopped (error
// result, counted `preempted`) when no engine is free, a stream under half its share is waiting,
// the frame has run kSliceS and four of the waiting stream's frames (its moving average of
// engine time; kColdSliceS while none of its frames has run), and its stream, with this
// frame's time so far, has used more than twice the waiting stream's usage plus kSliceS.
// Frames of like cost do not stop each other (a frame runs four of the other's frames), and a
// lone stream is never stopped (nobody waits).
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <map>
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
  /// stream, unregistered.
  void finish(YieldRequest* yield, double seconds);

  /// Charges `seconds` of other work of a frame (cluster-id tracking) to its stream.
  void charge(Stream& stream, double seconds);

  /// Engines that take from the slots (the share of each stream is in engines' time).
  void set_engines(int engines);

  static constexpr double kShareWindowS = 6.0;
  static constexpr double kSliceS = 0.1;
  static constexpr double kColdSliceS = 1.0;

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
    int64_t start_ns;
    double usage_at_start_s;
  };

  /// The slot's usage decayed to `now_ns` (steady clock).
  static double usage_at(SlotState& s, int64_t now_ns);
  /// Sets or withdraws the yield requests of the runs (see above). Under mutex_.
  void review_runs(int64_t now_ns);

  mutable std::mutex mutex_;
  std::condition_variable ready_;
  /// The streams whose slot holds a frame; that frame keeps its stream alive.
  std::vector<Stream*> waiting_;
  std::vector<Run> runs_;
  /// When each stream last offered a frame (steady clock), for the count of active streams;
  /// entries older than kShareWindowS are dropped, so it holds only recent stream ids.
  std::map<std::string, int64_t> offered_;
  uint64_t served_ = 0;
  int engines_ = 1;
  int idle_takers_ = 0;  ///< workers blocked in take()
  bool closed_ = false;
};

}  // namespace fq::daemon
