// fqd's state in the Prometheus text exposition format (version 0.0.4), for GET /metrics.
// Names follow Prometheus conventions (counters end in _total, latencies in seconds) and
// carry the words of the control socket and `fqctl counters --json`: frames_in is
// fq_frames_in_total{stream="…"}, stage latencies are fq_stage_latency_seconds{stream, stage}.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "daemon/pipeline/gpu_memory.h"
#include "daemon/pipeline/prometheus_format.h"
#include "daemon/stream/stream_registry.h"

namespace fq::daemon {

struct MetricsInput {
  /// Streams with series of their own, then the aggregate of every other (stream="other",
  /// always shown); StreamRegistry::metric_series.
  std::vector<NamedSeries> series;
  MetricSeries other;
  size_t streams = 0;                ///< streams fqd knows (fq_streams)
  std::vector<std::string> engines;  ///< engine names ("cpu", "cuda:<device name>")
  std::vector<GpuMemory> gpus;
  /// HTTP requests and connections refused, by reason (fq_http_refused_total{reason}).
  std::vector<std::pair<std::string, uint64_t>> http_refusals;
};

std::string prometheus_text(const MetricsInput& in);

}  // namespace fq::daemon
