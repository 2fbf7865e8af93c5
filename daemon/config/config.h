// fqd's configuration: one TOML file (see configs/fqd.toml for every key), validated
// completely at start so that a typo or a bad value stops the daemon with a clear message.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "common/status.h"
#include "daemon/config/security_config.h"
#include "daemon/config/service_config.h"
#include "daemon/config/stream_settings.h"
#include "kernels/engine.h"

namespace fq::daemon {

struct Endpoints {
  std::string ingest = "tcp://127.0.0.1:5555";   ///< PULL, bound; producers PUSH-connect
  std::string publish = "tcp://127.0.0.1:5556";  ///< PUB, bound; consumers SUB-connect
  std::string control = "tcp://127.0.0.1:5557";  ///< REP, bound; fqctl-style REQ clients

  bool operator==(const Endpoints&) const = default;
};

struct EngineConfig {
  EngineKind kind = EngineKind::kAuto;
  std::vector<int> gpus{0};         ///< one CUDA engine per listed device
  bool cpu_alongside_gpus = false;  ///< also run the CPU engine when GPU engines exist
  int cpu_threads = 0;              ///< threads of each CPU engine; 0 = all hardware threads
  int cpu_engines = 1;              ///< CPU engines (one worker thread each) when the CPU engine is used

  bool operator==(const EngineConfig&) const = default;
};

struct Caps {
  uint32_t max_vertices = 4'000'000;
  uint64_t max_frame_bytes = 256ull << 20;  ///< sum of all parts of one ingest message (also
                                            ///< the socket's per-part limit: ZMQ_MAXMSGSIZE)
  uint32_t max_streams = 64;
  uint32_t max_stream_id_bytes = 128;  ///< longer ids are refused (they are topics and log words)
  double stream_idle_s = 300.0;        ///< a stream without frames this long is forgotten; 0 = never
  /// A stream that is not configured keeps series of its own in /metrics while it has had a
  /// frame within this long; after it, its counts move to stream="other" (metric_series.h).
  /// 0 = while it is registered.
  double metric_series_idle_s = 30.0;
  /// Stream ids admitted: exact ids, or prefixes ending in '*'. Empty: every valid id.
  std::vector<std::string> allowed_streams;
  /// Expected neighbour visits of one frame (vertices x neighbours per vertex from the
  /// sigmas) above which its parameters are refused before the engine runs.
  double max_neighbour_work = 2e10;
  /// Kept frame buffers are freed after this long without frames (memory returns).
  double pool_idle_s = 30.0;
  /// Engine time of one frame (every run of a frame, clustering options included) after
  /// which the engine stops it at its next check and the frame gets an error result
  /// (counted time_limited); 0 = no limit.
  double engine_time_limit_s = 10.0;
  /// On stop (SIGTERM/SIGINT), frames already received may finish for this long; then the
  /// frame on each engine is stopped the same way and every frame left gets an error result.
  double stop_grace_s = 1.0;
  /// Results queued for a subscriber that does not keep up (the publish socket's SNDHWM);
  /// later ones are dropped for it and counted. Bounds what such a subscriber costs:
  /// (this + 1) x the largest result + 2 MiB of kernel buffer (docs/DAEMON.md).
  uint32_t max_subscriber_results = 16;
  /// Subscriptions of one subscriber, and bytes of their topics: a subscriber past either is
  /// cut (counted `subscriptions`), which frees what the publish socket kept for it.
  uint32_t max_subscriptions = 128;
  uint32_t max_subscription_bytes = 16384;
  /// Frames received and waiting for a decoder, and their bytes: when either is reached the
  /// connection holding most bytes gives up its newest frame (counted `superseded`;
  /// decode_queue.h). A frame over max_queued_bytes waits for an empty queue (backpressure).
  uint32_t max_queued_frames = 32;
  uint64_t max_queued_bytes = 256ull << 20;
  /// Host memory, in MiB, for what fqd keeps per stream: temporal histories, cluster id
  /// tracks, /latest copies and frames from admission to publish (daemon/stream/memory_account.h
  /// has what goes first at the limit); 0 = unbounded. 4 GiB: a fixed amount, not a share of
  /// the host's memory, since a container's limit is not what the host reports.
  uint64_t memory_budget_mb = 4096;

  bool operator==(const Caps&) const = default;
};

struct DaemonConfig {
  Endpoints endpoints;
  EngineConfig engine;
  int decode_threads = 0;  ///< frames decoded at once; 0 = half the hardware threads, at least 2
  int encode_threads = 0;  ///< results encoded at once; 0 = half the hardware threads, at least 2
  Caps caps;
  SecurityConfig security;
  StreamSettings defaults;
  std::map<std::string, StreamSettings> streams;  ///< per-stream overrides, resolved
  std::string log_level = "info";
  HttpConfig http;             ///< [http]: metrics, health, streams and the live viewer
  StatsLogConfig stats;        ///< [stats]: the periodic one-line log per stream
  SubIngestConfig sub_ingest;  ///< [ingest]: SUB-connect to producers too (scale-out)
  /// The file read ("" for the built-in defaults) and the line of each key in it, by dotted
  /// name ("http.token_file"; an array's items as "ingest.connect[1]"), for messages about a
  /// value found wrong after parsing (config_check.h).
  std::string source;
  std::map<std::string, int> lines;

  /// Replaces thread counts of 0 by their automatic value.
  void resolve_auto_threads();

  /// The settings a stream starts with: its [streams.<id>] entry or the defaults.
  const StreamSettings& settings_for(const std::string& stream_id) const;
  /// "file:line" of a key from the file (of its table when the file does not set it), "file"
  /// when neither is in the file, "built-in defaults" without a file.
  std::string where(const std::string& key) const;

  /// Equal settings and the same record of where they were read (source, lines).
  bool operator==(const DaemonConfig&) const = default;
};

/// Parses TOML text (`source` names it in messages). Unknown keys, wrong types and
/// out-of-range values are errors naming the key and line; so is text without a single key
/// unless `allow_empty` (a reload of an emptied file would reset every stream to the defaults).
Status parse_config(std::string_view text, const std::string& source, DaemonConfig& out,
                    bool allow_empty = true);

/// Reads and parses a file.
Status load_config(const std::string& path, DaemonConfig& out, bool allow_empty = true);

/// True for spdlog's level names: trace, debug, info, warn, error, critical, off.
bool valid_log_level(const std::string& level);

}  // namespace fq::daemon
