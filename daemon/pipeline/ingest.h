// The ingest thread as an object: it owns the PULL socket (with [ingest] connect also the SUB
// sockets, sub_ingest.h), checks each message's framing and header (cheap checks only, so it
// always keeps up) and hands frames to the decode pool. What only this thread touches is its
// own too: the arrival counter, the idle sweep's clock and when free pages went back last.
#pragma once

#include <cstdint>
#include <memory>
#include <set>
#include <string>
#include <thread>
#include <vector>
#include <zmq.hpp>

#include "common/non_copyable.h"
#include "daemon/pipeline/bounded_receive.h"
#include "daemon/pipeline/pipeline.h"
#include "daemon/pipeline/sub_producers.h"

namespace fq::daemon {

/// The receive mark of the ingest sockets, in messages per producer connection: what libzmq
/// holds for a connection before the ingest thread reads it (then that producer waits). The
/// thread waits only for a frame over caps.max_queued_bytes (decode_queue.h), so a connection
/// costs fqd at most this many messages plus the one being received, each within
/// caps.max_frame_bytes per part (ZMQ_MAXMSGSIZE) and in all once read (bounded_receive.h).
inline constexpr int kIngestMark = 4;

class Ingest : NonCopyable {
 public:
  /// `producers`: the SUB sockets of [ingest] connect (null: the PULL socket only), which take
  /// only the stream ids `assigned` (empty: all).
  Ingest(zmq::socket_t pull, Pipeline& p, std::unique_ptr<SubProducers> producers = nullptr,
         std::set<std::string> assigned = {});
  /// Joins the thread.
  ~Ingest();

  /// Starts the thread: it receives until the sockets' context is shut down, then closes them.
  void start();
  /// Waits for the thread to end; call after the context was shut down.
  void join();

 private:
  /// The PULL socket only: a blocking receive, woken once a second for the idle sweep.
  void run_pull();
  /// The PULL and the SUB sockets, polled by this one thread so that admission stays
  /// single-threaded (sub_ingest.cpp). A SUB message whose topic is not an assigned stream id
  /// is ignored without a count: ZeroMQ topics match by prefix ("cam1" also delivers "cam10"),
  /// and another fqd owns it.
  void run_with_producers();

  /// Receives one message from `socket` (`flags`: dontwait when a poll said it is there)
  /// within the ingest bounds (2 + wire::kMaxChunks parts, caps.max_frame_bytes in all, parts
  /// past them dropped as read) and hands it on: admitted, or refused (`oversized`) when over
  /// them. `assigned`: a SUB socket's stream ids, other topics are ignored (empty or null:
  /// all). False when there was no message.
  bool ingest_one(zmq::socket_t& socket, zmq::recv_flags flags,
                  const std::set<std::string>* assigned = nullptr);
  /// Builds the job for one ingest message: on success the frame for the decode pool,
  /// otherwise a job whose `error` is set (its stream id is the message's topic), or null for a
  /// malformed message from a producer without CURVE (refused and counted, never answered).
  FramePtr admit_message(std::vector<zmq::message_t>& parts);
  /// A message over the ingest bounds: an error of its stream, or refused under its topic.
  FramePtr refuse_oversized(const std::vector<zmq::message_t>& parts, Received why);
  /// A message that failed a check. From an authenticated producer, counted as its stream's
  /// error when the stream exists, otherwise refused before any state is made for it; from a
  /// producer without CURVE, dropped unanswered (null).
  FramePtr reject(FramePtr f, const std::string& topic, Refusal why, Status s);
  /// At most once a second: forgets idle streams and frees idle pools.
  void expire_idle_streams();
  void hand_back_free_pages(int64_t now);

  zmq::socket_t pull_;
  Pipeline& p_;
  std::unique_ptr<SubProducers> producers_;
  std::set<std::string> assigned_;
  LogLimiter errors_;
  /// Arrival index of the next ingest message, across streams (monotonic, so also within
  /// each stream; one counter instead of one per topic).
  uint64_t next_arrival_ = 0;
  int64_t last_sweep_ns_ = 0;        ///< idle-stream sweep (expire_idle_streams)
  int64_t last_malloc_trim_ns_ = 0;  ///< free pages last handed back
  uint64_t oversized_at_trim_ = 0;   ///< the pools' oversized_freed() then
  uint64_t arrival_at_trim_ = 0;     ///< next_arrival_ then
  uint64_t arrival_seen_ = 0;        ///< next_arrival_ at the last sweep
  int64_t arrival_seen_ns_ = 0;      ///< when it last changed
  std::thread thread_;
};

}  // namespace fq::daemon
