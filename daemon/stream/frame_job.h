// One frame on its way through fqd: what arrived, what each stage made of it, and its fate.
// Owned by exactly one stage at a time (moved through queues as a unique_ptr).
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>
#include <zmq.hpp>

#include "common/status.h"
#include "daemon/config/stream_settings.h"
#include "daemon/stream/memory_account.h"
#include "kernels/engine.h"
#include "wire/fq.pb.h"

namespace fq::daemon {

/// Wall-clock nanoseconds since the epoch: comparable with the producer's timestamps on
/// the same host (and across hosts whose clocks are synchronized).
inline int64_t wall_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

/// Milliseconds between two wall_ns() values.
inline double ms_between(int64_t from_ns, int64_t to_ns) {
  return static_cast<double>(to_ns - from_ns) * 1e-6;
}

class Stream;

struct FrameJob {
  std::string stream_id;
  /// The stream's state (stream.h), shared with the registry; null for a message refused
  /// before it had a stream. A stream that expires lives on until its last frame is done.
  std::shared_ptr<Stream> stream;
  uint64_t arrival = 0;                ///< arrival index (ingest order, increasing within a stream)
  uint64_t ticket = 0;                 ///< per-stream publish order, given when a worker takes it
  bool ticketed = false;               ///< the publisher orders ticketed results per stream
  wire::FrameHeader header;            ///< as received (empty for messages whose header failed)
  std::vector<zmq::message_t> chunks;  ///< Draco payloads, released after decode
  int64_t receive_ns = 0;
  /// The producer connection it came on (its socket number, ZMQ_SRCFD; -1 unknown): the
  /// decode queue serves connections in turn (decode_queue.h).
  int64_t connection = -1;
  bool large_in_decoder = false;  ///< counted by the decode queue until decoded() (decode_queue.h)

  StreamSettings settings;  ///< the stream's settings with the frame's overrides applied
  Mesh mesh;                ///< decoded input
  /// Triangles of each input chunk, as decode laid them out in `mesh`: a MESH result with the
  /// input's chunk count is cut the same way (wire::encode_frame_as), without a split.
  std::vector<uint32_t> chunk_triangles;
  FrameResult result;                   ///< engine output
  uint32_t distinct_clusters = 0;       ///< clusters found (result.num_clusters bounds tracked ids)
  std::string engine;                   ///< engine that processed it
  std::vector<PassTiming> timings;      ///< decode, wait, engine.<pass>..., encode
  std::vector<std::string> out_chunks;  ///< encoded result
  int64_t decoded_ns = 0;
  /// When its time limit (caps.engine_time_limit_s from the engine's start) ends: the engine
  /// and the cluster-id tracking after it both stop there (max(): no limit).
  std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();
  Status error;            ///< non-ok: published as an ERROR result
  bool preempted = false;  ///< stopped for another stream (counted `preempted`, not `errors`)
  bool refused = false;    ///< refused at admission: no stream state, counted in the refusals
  /// Came over CURVE from an allowed client key. Junk from such a producer (a malformed message,
  /// an undecodable frame) is its stream's error, published; from any other it is refused and
  /// dropped, since anyone who can connect could otherwise forge errors on every stream.
  bool authenticated = false;
  /// Its bytes on the host memory budget from admission until it is published or dropped
  /// (daemon/pipeline/memory_shed.h: charge_frame).
  MemoryCharge memory;
};

using FramePtr = std::unique_ptr<FrameJob>;

}  // namespace fq::daemon
