// The latency policy: one waiting slot per stream between decode and the engines.
// A newer frame replaces a waiting older one (superseded); a frame already older than its
// stream's budget when a worker is free is dropped (stale). Every frame that leaves the
// slots gets a per-stream ticket so results publish in arrival order even with several
// engines. Thread-safe. A stream's slot and ticket counter live in its Stream (stream.h),
// under this object's lock; only the streams with a frame waiting are listed here.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <vector>

#include "daemon/frame_job.h"
#include "daemon/stream.h"

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
    return waiting_.size();
  }

 private:
  mutable std::mutex mutex_;
  std::condition_variable ready_;
  /// The streams whose slot holds a frame; that frame keeps its stream alive.
  std::vector<Stream*> waiting_;
  uint64_t served_ = 0;
  bool closed_ = false;
};

}  // namespace fq::daemon
