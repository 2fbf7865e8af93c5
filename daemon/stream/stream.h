// One stream in fqd, all of its state in one object: its settings, counters and latency
// metrics (under its own lock), its waiting slot and ticket counter (the slots' lock), its
// publish order (the publisher thread), its cluster id track and its temporal filtering
// history (a lock each) and its latest result for the viewer (the latest results' lock).
// The registry owns it and every frame in flight shares it (FrameJob::stream), so expiry is
// one erase from the registry, and the last frame in flight frees the rest: no other owner
// keeps a map by stream id that could outlive the stream or grow with every id ever seen.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "common/non_copyable.h"
#include "daemon/config/stream_settings.h"
#include "daemon/stream/frame_job.h"
#include "daemon/stream/memory_account.h"
#include "daemon/stream/metric_series.h"
#include "daemon/stream/stage_metrics.h"
#include "kernels/label_tracking.h"
#include "kernels/temporal.h"

namespace fq::daemon {

struct StreamSnapshot {
  std::string stream_id;
  StreamCounters counters;
  std::map<std::string, Percentiles> stages;
  std::map<std::string, LatencyHistogram> histograms;  ///< since start, by stage (for /metrics)
};

/// A stream's counters and latency samples as copied under its lock. Percentiles are computed
/// from the copy (summarize), after the lock is released: a frame that counts or records
/// never waits for them.
struct StreamSamples {
  std::string stream_id;
  StreamCounters counters;
  StageMetrics metrics;
};
StreamSnapshot summarize(const StreamSamples& s);

/// The waiting slot (latency_policy.h); FrameSlots' lock guards it.
struct SlotState {
  FramePtr waiting;
  uint64_t last_taken_arrival = 0;
  bool taken_any = false;
  uint64_t next_ticket = 0;
  uint64_t served = 0;  ///< when it was last handed out (FrameSlots' count then); 0 = never
  double usage_s = 0;   ///< recent engine time, decayed to usage_ns (steady clock)
  int64_t usage_ns = 0;
  double cost_s = 0;  ///< engine time of its frames (moving average); 0 = none seen yet
  /// Its last run was preempted: its next one is not (guaranteed progress).
  bool preempted = false;
  int64_t last_receive_ns = 0;  ///< the newest receipt of its frames offered (wall clock)
  double interval_s = 0;        ///< time between its frames (moving average); 0 = unknown
};

/// Results held back until the earlier tickets are published (publisher.h); publisher thread only.
struct PublishOrder {
  uint64_t next = 0;
  std::map<uint64_t, FramePtr> held;
};

/// The previous frames' cluster ids (label_tracks.h): the previous frame's grid, ids and votes,
/// and the buffers the next frame is tracked in (about 120 bytes a vertex: tens of MB for a
/// large frame).
struct LabelTrack {
  std::mutex mutex;
  LabelTracker tracker;
  MemoryCharge charge;  ///< its bytes on the memory budget (memory_account.h)
};

/// Its last result for temporal filtering (kernels/temporal.h) and the arrival of the frame
/// that made it (stream_history.h): tens of MB for a large frame, like the label track.
struct TemporalTrack {
  std::mutex mutex;
  TemporalHistory history;
  uint64_t last_arrival = 0;
  MemoryCharge charge;  ///< its bytes on the memory budget (memory_account.h)
};

struct LatestResult;
/// The latest result kept for the viewer (latest_results.h); LatestResults' lock guards it.
struct LatestSlot {
  std::shared_ptr<const LatestResult> latest;
  uint64_t index = 0;
  std::chrono::steady_clock::time_point watched_until;
  std::shared_ptr<const std::vector<uint32_t>> faces;  ///< the last POSITIONS result's
  uint64_t faces_id = 0;
  MemoryCharge charge;  ///< `latest` and `faces` on the memory budget (memory_account.h)
};

class Stream : NonCopyable {
 public:
  /// `memory`: the budget what it keeps is charged to (null: none).
  Stream(std::string id, const StreamSettings& settings, int64_t now_ns, MemoryAccount* memory = nullptr);
  ~Stream();

  const std::string& id() const { return id_; }

  StreamSettings settings() const;
  void set_settings(const StreamSettings& s);
  void count(Counter c, uint64_t n = 1);
  void record(const std::string& stage, double ms);
  /// Counters and samples, copied under the stream's lock (held for the copy only).
  StreamSamples samples() const;
  /// Its counters and latency histograms since they last moved to the /metrics aggregate.
  MetricSeries own_series() const;
  /// Adds its counts since the last move to `other` (the aggregate, under its owner's lock):
  /// its own series start again from zero, and no count is moved twice.
  void move_series(MetricSeries& other);

  /// When a frame (or a control request) last found it, wall_ns(); the registry expires it.
  std::atomic<int64_t> last_seen_ns{0};
  /// A frame has found it (the registry's lock): a stream only set_params made, without one,
  /// gives its slot up to a producer's new stream when max_streams are registered.
  bool fed = false;
  /// The memory budget its history, track and /latest copy are charged to (may be null).
  MemoryAccount* const memory;
  /// When a frame last used its history or track (wall_ns()): the budget sheds the stream's
  /// that was used longest ago first (memory_account.h).
  std::atomic<int64_t> kept_ns{0};

  SlotState slot;          ///< FrameSlots' lock
  PublishOrder order;      ///< the publisher thread
  LabelTrack track;        ///< its own lock
  TemporalTrack temporal;  ///< its own lock
  LatestSlot latest;       ///< LatestResults' lock

 private:
  const std::string id_;
  mutable std::mutex mutex_;  ///< settings_, counters_, metrics_
  StreamSettings settings_;
  StreamCounters counters_;
  StageMetrics metrics_;
  MetricSeries moved_;  ///< its counts when they last moved to the /metrics aggregate
};

using StreamPtr = std::shared_ptr<Stream>;

}  // namespace fq::daemon
