// The queues and shared state between fqd's threads:
//   ingest thread -> decode_queue (bounded: backpressure) -> decode pool -> slots (latency policy)
//   -> engine workers (one per engine) -> encode_queue -> encode pool
//   -> publish_queue -> publisher thread (owns the PUB socket).
// Error results skip ahead to publish_queue from whichever stage found the problem.
#pragma once

#include <atomic>

#include "daemon/config/config.h"
#include "daemon/config/live_caps.h"
#include "daemon/pipeline/curve_auth.h"
#include "daemon/pipeline/decode_queue.h"
#include "daemon/pipeline/engine_busy.h"
#include "daemon/pipeline/latency_policy.h"
#include "daemon/pipeline/log_limiter.h"
#include "daemon/pipeline/memory_shed.h"
#include "daemon/pipeline/object_pool.h"
#include "daemon/pipeline/stage_cpu.h"
#include "daemon/pipeline/work_queue.h"
#include "daemon/stream/frame_job.h"
#include "daemon/stream/latest_results.h"
#include "daemon/stream/stream_admission.h"
#include "daemon/stream/stream_registry.h"

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
  Pipeline(const DaemonConfig& c, StreamRegistry& r, LiveCaps& live_caps)
      : config(c),
        registry(r),
        caps(live_caps),
        results(
            8, [](const FrameResult& x) { return bytes_held(x.positions) + bytes_held(x.labels); },
            [](const FrameResult& x) { return bytes_used(x.positions) + bytes_used(x.labels); }),
        meshes(
            8, [](const Mesh& m) { return bytes_held(m.positions) + bytes_held(m.triangles); },
            [](const Mesh& m) { return bytes_used(m.positions) + bytes_used(m.triangles); }),
        latest(r) {
    // The budget's order (memory_shed.h); removed before the pipeline goes, the registry stays.
    r.memory().set_shedder([this](uint64_t need, Shed upto, const void* keep) {
      shed_memory(registry, latest, need, upto, keep);
    });
  }
  ~Pipeline() { registry.memory().set_shedder({}); }
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;

  const DaemonConfig& config;  ///< as started; the caps that SIGHUP changes are in `caps`
  StreamRegistry& registry;
  LiveCaps& caps;
  /// With [security]: the client keys allowed now; a message from a key no longer in it is
  /// refused and its connection cut (null without CURVE).
  const ClientKeys* keys = nullptr;
  DecodeQueue decode_queue;  ///< bounded; at most one frame of each stream
  FrameSlots slots;
  WorkQueue<FramePtr> encode_queue;
  WorkQueue<FramePtr> publish_queue;
  // Lines any producer can cause, each kind at most 5 a second (log_limiter.h).
  LogLimiter refusal_log;  ///< frames refused at admission
  LogLimiter fail_log;     ///< error results
  LogLimiter drop_log;     ///< superseded and stale frames (debug)
  LogLimiter expiry_log;   ///< streams expired
  /// Engine outputs, reused: the engines keep a result's buffers.
  ObjectPool<FrameResult> results;
  /// Decoded input meshes, reused: decode_frame keeps their capacity, so a steady stream
  /// stops allocating (and faulting in) tens of MB per frame for 4M-triangle frames.
  ObjectPool<Mesh> meshes;
  LatestResults latest;    ///< each watched stream's last result (HTTP viewer)
  EngineBusy engine_busy;  ///< time on frames per engine (/metrics)
  StageCpu stage_cpu;      ///< host CPU per stage (/metrics, fqstreambench)
  /// Set when a stopping daemon's grace (caps.stop_grace_s) has passed: every engine run
  /// ends at its next check, and frames still waiting get an error result at once.
  std::atomic<bool> cancel_engines{false};

  /// Marks `frame` failed (message logged) and sends it straight to the publisher.
  void fail(FramePtr frame, Status why);
  /// Returns the frame's mesh and result buffers to their pools once it is published or dropped.
  void recycle(FrameJob& frame);
};

/// Decode pool worker: decode, check the mesh and the parameters, offer to the slots.
void run_decode_worker(Pipeline& p);
/// Engine worker: take from the slots, run the engine, hand to the encode pool.
void run_engine_worker(Pipeline& p, Engine& engine);
/// Encode pool worker: encode the result chunks, hand to the publisher.
void run_encode_worker(Pipeline& p);

}  // namespace fq::daemon
