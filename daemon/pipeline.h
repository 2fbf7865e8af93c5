// The queues and shared state between fqd's threads:
//   ingest thread -> decode_queue -> decode pool -> slots (latency policy)
//   -> engine workers (one per engine) -> encode_queue -> encode pool
//   -> publish_queue -> publisher thread (owns the PUB socket).
// Error results skip ahead to publish_queue from whichever stage found the problem.
#pragma once

#include <atomic>
#include <map>
#include <mutex>
#include <string>

#include "daemon/config.h"
#include "daemon/engine_busy.h"
#include "daemon/frame_job.h"
#include "daemon/label_tracks.h"
#include "daemon/latency_policy.h"
#include "daemon/latest_results.h"
#include "daemon/object_pool.h"
#include "daemon/stage_cpu.h"
#include "daemon/stream_admission.h"
#include "daemon/stream_registry.h"
#include "daemon/work_queue.h"

namespace fq::daemon {

template <class V>
size_t bytes_held(const V& v) {
  return v.capacity() * sizeof(typename V::value_type);
}
template <class V>
size_t bytes_used(const V& v) {
  return v.size() * sizeof(typename V::value_type);
}

struct Pipeline {
  Pipeline(const DaemonConfig& c, StreamRegistry& r)
      : config(c),
        registry(r),
        results(8, [](const FrameResult& x) { return bytes_held(x.positions) + bytes_held(x.labels); },
                [](const FrameResult& x) { return bytes_used(x.positions) + bytes_used(x.labels); }),
        meshes(8, [](const Mesh& m) { return bytes_held(m.positions) + bytes_held(m.triangles); },
               [](const Mesh& m) { return bytes_used(m.positions) + bytes_used(m.triangles); }) {}

  const DaemonConfig& config;
  StreamRegistry& registry;
  WorkQueue<FramePtr> decode_queue;
  FrameSlots slots;
  WorkQueue<FramePtr> encode_queue;
  WorkQueue<FramePtr> publish_queue;
  /// Arrival index of the next ingest message, across streams (monotonic, so also within
  /// each stream; one counter instead of one per topic). Ingest thread only.
  uint64_t next_arrival = 0;
  LogLimiter refusal_log;  ///< ingest thread only
  int64_t last_sweep_ns = 0;        ///< idle-stream sweep (expire_idle_streams), ingest thread only
  int64_t last_malloc_trim_ns = 0;  ///< free pages last handed back, ingest thread only
  uint64_t oversized_at_trim = 0;   ///< the pools' oversized_freed() then, ingest thread only
  uint64_t arrival_at_trim = 0;     ///< next_arrival then, ingest thread only
  uint64_t arrival_seen = 0;        ///< next_arrival at the last sweep, ingest thread only
  int64_t arrival_seen_ns = 0;      ///< when it last changed, ingest thread only
  /// Engine outputs, reused: the engines keep a result's buffers.
  ObjectPool<FrameResult> results;
  /// Decoded input meshes, reused: decode_frame keeps their capacity, so a steady stream
  /// stops allocating (and faulting in) tens of MB per frame for 4M-triangle frames.
  ObjectPool<Mesh> meshes;
  LatestResults latest;                      ///< each watched stream's last result (HTTP viewer)
  LabelTracks label_tracks;                  ///< stable cluster ids per stream
  EngineBusy engine_busy;                    ///< time on frames per engine (/metrics)
  StageCpu stage_cpu;                        ///< host CPU per stage (/metrics, fqstreambench)
  /// Set when a stopping daemon's grace (caps.stop_grace_s) has passed: every engine run
  /// ends at its next check, and frames still waiting get an error result at once.
  std::atomic<bool> cancel_engines{false};

  /// Marks `frame` failed (message logged) and sends it straight to the publisher.
  void fail(FramePtr frame, Status why);
  /// Returns the frame's mesh and result buffers to their pools once it is published or dropped.
  void recycle(FrameJob& frame);

  /// Notes that `frame` is being queued for decode (ingest thread).
  void note_queued(const FrameJob& frame);
  /// True when a newer frame of the same stream is already queued: a decoder that pops an
  /// older one skips it (superseded), as the newer one would take its slot anyway. This
  /// keeps a backlog from building up in front of the decoders.
  bool newer_queued(const FrameJob& frame);
  /// Drops what the pipeline keeps for a stream that expired (ingest thread).
  void forget(const std::string& stream_id);

 private:
  std::mutex newest_mutex_;
  std::map<std::string, uint64_t> newest_queued_;  ///< per stream, the last arrival queued
};

/// Decode pool worker: decode, check the mesh and the parameters, offer to the slots.
void run_decode_worker(Pipeline& p);
/// Engine worker: take from the slots, run the engine, hand to the encode pool.
void run_engine_worker(Pipeline& p, Engine& engine);
/// Encode pool worker: encode the result chunks, hand to the publisher.
void run_encode_worker(Pipeline& p);

}  // namespace fq::daemon
