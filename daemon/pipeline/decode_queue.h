// Frames received and waiting for a decoder, bounded in frames and in bytes (caps.
// max_queued_frames, caps.max_queued_bytes). 300 frames of 4 MiB sent while the decoders were
// busy took fqd from 64 to 2,278 MB, all of them later dropped as stale. Now:
//  - a stream has at most one frame waiting: a newer one takes the older one's place (the older
//    is handed back to be counted `superseded`; it would lose its slot to the newer anyway);
//  - when the queue is full, push() waits: the ingest thread stops reading, ZeroMQ's receive
//    mark (a few messages per connection) fills, and producers are held back by their own send
//    marks (PUSH waits, PUB drops), so nothing piles up in fqd.
// A frame larger than max_queued_bytes is let in alone, when the queue is empty.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>

#include "daemon/stream/frame_job.h"

namespace fq::daemon {

class DecodeQueue {
 public:
  /// The bounds (at start, and when SIGHUP changes them).
  void set_bounds(size_t max_frames, uint64_t max_bytes);

  /// Queues `f`: an older frame of its stream still waiting comes back in `superseded`; then
  /// waits for room. False (and `f` dropped) when the queue is closed.
  bool push(FramePtr f, FramePtr& superseded);
  /// Blocks until a frame is waiting; nothing once the queue is closed and empty.
  std::optional<FramePtr> pop();
  /// Wakes every waiter; frames already queued are still handed out.
  void close();

  size_t frames() const;
  uint64_t bytes() const;

 private:
  static uint64_t bytes_of(const FrameJob& f);
  bool room_for(uint64_t bytes) const;  // with the lock held

  mutable std::mutex mutex_;
  std::condition_variable ready_, room_;
  std::deque<FramePtr> items_;
  uint64_t bytes_ = 0;
  size_t max_frames_ = 32;
  uint64_t max_bytes_ = 256ull << 20;
  bool closed_ = false;
};

}  // namespace fq::daemon
