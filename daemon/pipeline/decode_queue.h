// Frames received and waiting for a decoder, bounded in frames and in bytes (caps.
// max_queued_frames, caps.max_queued_bytes), served in turn across producer connections and
// across the streams of each. 300 frames of 4 MiB sent while the decoders were busy took fqd
// from 64 to 2,278 MB, all of them later dropped as stale; later, a stream at 5 fps got 0 of 75
// results beside 8 connections sending 12 MB frames on 48 stream ids, because a newer frame
// went to the back of one queue in place of its stream's waiting one, so a stream that kept
// sending never reached the front. Now:
//  - each connection (the frame's `connection`, its socket number) has a lane of places, one
//    per stream, in the order the streams came; a newer frame of a stream takes its older
//    one's place (the older is handed back, to be counted `superseded`);
//  - a decoder takes from the lanes in turn, by bytes (deficit round robin: every lane earns
//    credit at the same rate, a lane is served when its credit covers its first frame), so a
//    connection of heavy frames gets the decoders' bytes, not their turns, and a lane takes its
//    streams in turn;
//  - when the queue is full, the lane holding most bytes (the new frame counted in its own)
//    gives up its newest place: another connection's frame, or the new frame itself when its
//    own connection holds most; both are handed back (counted `superseded`). So the ingest
//    thread does not wait for a connection that sends more than the decoders take while
//    others have frames queued, and a lighter connection's frame always gets in. A connection
//    alone in the queue waits for room instead (nobody else is served later for it);
//  - a frame larger than max_queued_bytes is let in alone: its push waits until the queue is
//    empty (the ingest thread then waits, ZeroMQ's receive mark fills and producers wait).
//  - while small frames (up to kSmallFrameBytes) have come in the last kSmallWindowS, one
//    decoder is kept for them: larger frames take at most all decoders but one. A decoder is
//    held for a frame's whole decode (seconds for a 12 MB frame on a busy machine), so turns
//    alone let frames that large hold every decoder while a light stream's frames were
//    superseded behind them.
// What libzmq holds besides: docs/RELIABILITY.md ("Limits").
#pragma once

#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <vector>

#include "daemon/stream/frame_job.h"

namespace fq::daemon {

class DecodeQueue {
 public:
  /// The bounds (at start, and when SIGHUP changes them).
  void set_bounds(size_t max_frames, uint64_t max_bytes);

  /// Queues `f` in its stream's place (see above); the frames that lost theirs (its stream's
  /// older frame, frames shed from a full queue, `f` itself when its connection gives way) are
  /// appended to `dropped`. Waits only for a frame over the byte bound. False (and `f`
  /// dropped) when the queue is closed.
  bool push(FramePtr f, std::vector<FramePtr>& dropped);
  /// Blocks until a frame is waiting; nothing once the queue is closed and empty.
  std::optional<FramePtr> pop();
  /// The decode workers that pop (one is kept for small frames when there are two or more).
  void set_decoders(int decoders);
  /// A frame popped has been decoded (or dropped): its decoder is free again.
  void decoded(const FrameJob& f);
  /// Wakes every waiter; frames already queued are still handed out.
  void close();

  size_t frames() const;
  uint64_t bytes() const;

  static constexpr uint64_t kSmallFrameBytes = 1 << 20;
  static constexpr double kSmallWindowS = 2.0;

 private:
  /// One connection's places, oldest stream first.
  struct Lane {
    int64_t connection = -1;
    std::vector<FramePtr> places;
    uint64_t bytes = 0;
    uint64_t credit = 0;  ///< bytes it may take before the lanes behind it (deficit round robin)
  };

  static uint64_t bytes_of(const FrameJob& f);
  bool full(uint64_t more_bytes, size_t more_frames) const;  // with the lock held
  /// Drops the newest place of the lane holding most bytes (`incoming` counted in `lane`) into
  /// `dropped`, or `incoming` itself when that lane is its own. With the lock held.
  void shed(Lane& lane, FramePtr& incoming, std::vector<FramePtr>& dropped);
  Lane& lane_of(int64_t connection);  // with the lock held; made when missing
  /// Whether a frame of `bytes` may take a free decoder now (see above). With the lock held.
  bool may_decode(uint64_t bytes) const;
  void erase_empty_lanes();  // with the lock held

  mutable std::mutex mutex_;
  std::condition_variable ready_, empty_, room_;
  std::vector<Lane> lanes_;  ///< in turn order; next_ is the next to be asked
  size_t next_ = 0;
  size_t frames_ = 0;
  uint64_t bytes_ = 0;
  size_t max_frames_ = 32;
  uint64_t max_bytes_ = 256ull << 20;
  int decoders_ = 2;
  int large_in_decoders_ = 0;  ///< decoders busy with frames over kSmallFrameBytes
  int64_t small_seen_ns_ = 0;  ///< when a small frame last came (steady clock); 0 never
  bool closed_ = false;
};

}  // namespace fq::daemon
