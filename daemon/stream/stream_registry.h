// Every stream fqd has seen or been configured with, as Stream objects (stream.h) by id.
// The registry owns them; frames in flight share them. Thread-safe: the ingest, worker,
// publisher, control and HTTP threads all use it. Its lock guards the map only: a stream's
// settings, counters and metrics are under the stream's own lock.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "daemon/config/config.h"
#include "daemon/stream/stream.h"
#include "daemon/stream/stream_admission.h"

namespace fq::daemon {

class StreamRegistry {
 public:
  explicit StreamRegistry(const DaemonConfig& config);

  /// The stream a frame belongs to, registering it (from its config entry or the defaults)
  /// on first sight, and noting it as active at `now_ns`. When the stream is new and
  /// max_streams are already registered, the stream that only control requests made (no frame
  /// ever found it, not configured) and that was touched longest ago gives its slot up; null
  /// when there is none. The only call that registers a stream from a frame: the ingest thread
  /// calls it once the stream id has been admitted.
  StreamPtr admit(const std::string& stream_id, int64_t now_ns);
  /// A registered stream; null when unknown.
  StreamPtr find(const std::string& stream_id) const;

  /// The stream's settings, registering it as admit() does (at the current time); false when
  /// the stream is new and max_streams are already registered (the control socket's
  /// set_params reads them first).
  bool settings(const std::string& stream_id, StreamSettings& out);
  /// Replaces a stream's settings (registering it); the caller has validated them. This does
  /// not keep the stream from expiring: only configured streams are pinned.
  bool set_settings(const std::string& stream_id, const StreamSettings& s);
  /// The settings of a registered stream; false when unknown.
  bool find(const std::string& stream_id, StreamSettings& out) const;

  /// Forgets the streams that are not configured and have had no frame for `idle_s` seconds;
  /// returns their ids. Frames of theirs still in flight finish with the stream they hold.
  std::vector<std::string> expire_idle(int64_t now_ns, double idle_s);
  /// Replaces the configured settings (a reloaded config's [defaults] and [streams.*]): every
  /// registered stream gets its entry's or the new defaults (run-time changes are replaced),
  /// newly configured streams are registered, and new streams start from them. Streams no
  /// longer configured are no longer pinned: they expire once idle. Counters stay.
  void reload(const StreamSettings& defaults, const std::map<std::string, StreamSettings>& streams);

  std::vector<std::string> list() const;
  /// Every registered stream (the memory budget's shedder walks them).
  std::vector<StreamPtr> all() const;
  /// One stream (false when unknown) or, with an empty id, every stream. Each stream's
  /// counters and samples are copied under its lock, one stream at a time and without the
  /// registry's lock; the percentiles are computed after every lock is released. `copied`
  /// (may be empty) runs between the two (tests show with it that no lock is held then).
  bool snapshot(const std::string& stream_id, std::vector<StreamSnapshot>& out,
                const std::function<void()>& copied = {}) const;

  /// What /metrics shows of the streams at `now_ns` (metric_series.h): in `named`, the series of
  /// every stream that has series of its own (has_own_series); in `other`, the counts of every
  /// other stream and of every stream that expired, summed. A stream that loses its own series
  /// moves its counts to `other` then, and starts from zero should it get them back.
  void metric_series(int64_t now_ns, double idle_s, std::vector<NamedSeries>& named, MetricSeries& other);
  /// The ids metric_series() names at `now_ns`.
  std::vector<std::string> own_series_ids(int64_t now_ns, double idle_s) const;

  /// Messages refused before any stream state was made for them, by reason.
  RefusalCounters& refusals() { return refusals_; }
  const RefusalCounters& refusals() const { return refusals_; }

  /// The host memory budget what the streams keep is charged to (memory_account.h); it
  /// outlives every stream of the registry.
  MemoryAccount& memory() { return memory_; }
  const MemoryAccount& memory() const { return memory_; }

 private:
  // Registers; null when full. `frame`: for a frame, which may take the slot of a stream no
  // frame has found (see admit()), and marks the stream fed.
  StreamPtr entry(const std::string& stream_id, int64_t now_ns, bool frame);
  StreamPtr touch(const std::string& stream_id, int64_t now_ns, bool frame);
  const StreamSettings& configured(const std::string& stream_id) const;
  /// Configured, or a frame within `idle_s` (0: every registered stream); never a stream named
  /// like the aggregate. Under mutex_.
  bool has_own_series(const std::string& id, const Stream& s, int64_t now_ns, double idle_s) const;

  const DaemonConfig& config_;
  MemoryAccount memory_;      ///< before streams_: destroyed after them, which credit it
  mutable std::mutex mutex_;  ///< the three members below
  StreamSettings defaults_;   ///< [defaults], replaced by reload()
  std::map<std::string, StreamSettings> configured_;  ///< [streams.*]: pinned; replaced by reload()
  std::map<std::string, StreamPtr> streams_;
  RefusalCounters refusals_;
  std::mutex other_mutex_;  ///< other_ (taken before a stream's lock)
  MetricSeries other_;      ///< /metrics' stream="other": streams without own series, expired ones
};

}  // namespace fq::daemon
