// The latency policy: one waiting slot per stream between decode and the engines.
// A newer frame replaces a waiting older one (superseded); a frame already older than its
// stream's budget when a worker is free is dropped (stale). Every frame that leaves the
// slots gets a per-stream ticket so results publish in arrival order even with several
// engines. Thread-safe.
//
// Fairness by engine time. Each stream's recent engine time (seconds of engine and cluster-id
// tracking, decayed with time constant kShareWindowS) is its usage; a free engine takes the
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

#include "daemon/frame_job.h"
#include "kernels/cancel_token.h"

namespace fq::daemon {

/// True when a frame received at `receive_ns` is older than `budget_ms` at `now_ns`.
inline bool is_stale(int64_t receive_ns, int64_t now_ns, double budget_ms) {
  return ms_between(receive_ns, now_ns) > budget_ms;
}

class FrameSlots {
 public:
  /// Puts a decoded frame in its stream's slot. Returns the frame that lost: the older
  /// frame it replaced, or the frame itself when a newer one of its stream is already
  /// waiting or taken (decode finished out of order); null when nothing was replaced.
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
  void charge(const std::string& stream_id, double seconds);

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
    return waiting_;
  }

 private:
  struct Stream {
    FramePtr waiting;
    uint64_t last_taken_arrival = 0;
    bool taken_any = false;
    uint64_t next_ticket = 0;
    uint64_t served = 0;  ///< when it was last handed out (served_ at the time); 0 = never
    double usage_s = 0;   ///< recent engine time, decayed to usage_ns
    int64_t usage_ns = 0;
    int64_t offered_ns = 0;  ///< last frame offered (steady clock); 0 = never
    double cost_s = 0;       ///< engine time of its frames (moving average); 0 = none seen yet
  };
  /// A frame on an engine, taken with a YieldRequest.
  struct Run {
    std::string stream_id;
    YieldRequest* yield;
    int64_t start_ns;
    double usage_at_start_s;
  };

  /// The stream's usage decayed to `now_ns` (steady clock).
  static double usage_at(Stream& s, int64_t now_ns);
  /// Sets or withdraws the yield requests of the runs (see above). Under mutex_.
  void review_runs(int64_t now_ns);

  mutable std::mutex mutex_;
  std::condition_variable ready_;
  std::map<std::string, Stream> streams_;
  std::vector<Run> runs_;
  size_t waiting_ = 0;
  uint64_t served_ = 0;
  int engines_ = 1;
  int idle_takers_ = 0;  ///< workers blocked in take()
  bool closed_ = false;
};

}  // namespace fq::daemon
