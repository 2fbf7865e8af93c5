// The latency policy: one waiting slot per stream between decode and the engines.
// A newer frame replaces a waiting older one (superseded); a frame already older than its
// stream's budget when a worker is free is dropped (stale). Every frame that leaves the
// slots gets a per-stream ticket so results publish in arrival order even with several
// engines. Thread-safe.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "daemon/frame_job.h"

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

  /// Blocks until a frame is waiting, then hands one out round robin across streams (the stream
  /// served least recently first, the oldest frame among equals) to the calling worker in `out`, ticketed; frames found stale on the way are
  /// moved to `stale` (and `out` stays null when nothing fresh is left). False once closed
  /// and empty. With `wait`, also returns (true, `out` null) after waiting that long for a frame.
  bool take(FramePtr& out, std::vector<FramePtr>& stale,
            std::chrono::milliseconds wait = std::chrono::milliseconds::max());

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
  };

  mutable std::mutex mutex_;
  std::condition_variable ready_;
  std::map<std::string, Stream> streams_;
  size_t waiting_ = 0;
  uint64_t served_ = 0;
  bool closed_ = false;
};

}  // namespace fq::daemon
