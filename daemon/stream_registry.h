// Every stream fqd has seen or been configured with: its current settings (changeable at
// run time through the control socket), its counters and its latency metrics.
// Thread-safe: the ingest, worker, publisher and control threads all use it.
#pragma once

#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "daemon/config.h"
#include "daemon/stage_metrics.h"
#include "daemon/stream_admission.h"

namespace fq::daemon {

/// What happened to a stream's frames. Once the pipeline is idle,
/// frames_in == frames_out + errors + superseded + dropped_stale.
struct StreamCounters {
  uint64_t frames_in = 0;      ///< ingest messages attributed to the stream
  uint64_t frames_out = 0;     ///< results published with status OK or LATE
  uint64_t superseded = 0;     ///< replaced in the waiting slot by a newer frame
  uint64_t dropped_stale = 0;  ///< older than the budget when a worker was free
  uint64_t late = 0;           ///< published after the budget (also in frames_out)
  uint64_t errors = 0;         ///< error results published
  uint64_t time_limited = 0;   ///< stopped at caps.engine_time_limit_s (also in errors)
  /// Times a subscriber's queue was found full (caps.max_subscriber_results), so that it
  /// missed the result being published; ZeroMQ then skips that subscriber without telling
  /// until it has read half its queue, so one overflow may stand for many missed results.
  /// Not part of the sum above: the results were published.
  uint64_t subscriber_overflows = 0;
  /// Results whose producer send time was more than an hour before publish or after it (a
  /// wrong or forged clock): their send_to_publish is left out of the metrics, not folded
  /// into the histograms. Not part of the sum above.
  uint64_t bad_send_time = 0;
  /// Results published with the engine's cluster numbering because id tracking was cut by
  /// the frame's time limit or the stop (also in frames_out).
  uint64_t untracked = 0;
  /// Frames stopped on the engine to serve a stream within its share of engine time (also in
  /// errors; see latency_policy.h).
  uint64_t preempted = 0;
};

enum class Counter {
  kIn,
  kOut,
  kSuperseded,
  kDroppedStale,
  kLate,
  kErrors,
  kTimeLimited,
  kSubscriberOverflows,
  kBadSendTime,
  kUntracked,
  kPreempted
};

struct StreamSnapshot {
  std::string stream_id;
  StreamCounters counters;
  std::map<std::string, Percentiles> stages;
  std::map<std::string, LatencyHistogram> histograms;  ///< since start, by stage (for /metrics)
};

class StreamRegistry {
 public:
  explicit StreamRegistry(const DaemonConfig& config);

  /// The stream's settings, registering it (from its config entry or the defaults) on
  /// first sight, and noting it as active at `now_ns`. False when the stream is new and
  /// max_streams are already registered. The only call that registers a stream from a frame:
  /// the ingest thread calls it once the stream id has been admitted.
  bool settings(const std::string& stream_id, StreamSettings& out, int64_t now_ns = 0);
  /// Replaces a stream's settings (registering it); the caller has validated them. A stream
  /// whose settings were set this way, like one from the config, never expires.
  bool set_settings(const std::string& stream_id, const StreamSettings& s);
  /// Forgets streams that are neither configured nor set at run time and have had no frame
  /// for `idle_s` seconds; returns their ids.
  std::vector<std::string> expire_idle(int64_t now_ns, double idle_s);
  /// The settings of a registered stream; false when unknown.
  bool find(const std::string& stream_id, StreamSettings& out) const;
  /// Replaces the configured settings (a reloaded config's [defaults] and [streams.*]): every
  /// registered stream gets its entry's or the new defaults (run-time changes are replaced),
  /// newly configured streams are registered, and new streams start from them. Counters stay.
  void reload(const StreamSettings& defaults, const std::map<std::string, StreamSettings>& streams);

  void count(const std::string& stream_id, Counter c, uint64_t n = 1);
  void record(const std::string& stream_id, const std::string& stage, double ms);

  std::vector<std::string> list() const;
  /// One stream (false when unknown) or, with an empty id, every stream.
  bool snapshot(const std::string& stream_id, std::vector<StreamSnapshot>& out) const;

  /// Messages refused before any stream state was made for them, by reason.
  RefusalCounters& refusals() { return refusals_; }
  const RefusalCounters& refusals() const { return refusals_; }

 private:
  struct Entry {
    StreamSettings settings;
    StreamCounters counters;
    StageMetrics metrics;
    int64_t last_seen_ns = 0;
    bool pinned = false;  ///< configured or set through the control socket: never expires
  };
  Entry* entry(const std::string& stream_id);  // registers; null when full
  Entry* existing(const std::string& stream_id);  // null when unknown
  StreamSnapshot snapshot_of(const std::string& id, const Entry& e) const;

  const StreamSettings& configured(const std::string& stream_id) const;

  const DaemonConfig& config_;
  StreamSettings defaults_;                           ///< [defaults], replaced by reload()
  std::map<std::string, StreamSettings> configured_;  ///< [streams.*], replaced by reload()
  mutable std::mutex mutex_;
  std::map<std::string, Entry> streams_;
  RefusalCounters refusals_;
};

}  // namespace fq::daemon
