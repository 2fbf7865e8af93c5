// fqd's state in the Prometheus text exposition format (version 0.0.4), for GET /metrics.
// Names follow Prometheus conventions (counters end in _total, latencies in seconds) and
// carry the words of the control socket and `fqctl counters --json`: frames_in is
// fq_frames_in_total{stream="…"}, stage latencies are fq_stage_latency_seconds{stream, stage}.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "daemon/gpu_memory.h"
#include "daemon/stream_registry.h"

namespace fq::daemon {

struct MetricsInput {
  std::vector<StreamSnapshot> streams;
  std::vector<std::string> engines;  ///< engine names ("cpu", "cuda:<device name>")
  std::vector<GpuMemory> gpus;
  /// HTTP requests and connections refused, by reason (fq_http_refused_total{reason}).
  std::vector<std::pair<std::string, uint64_t>> http_refusals;
};

std::string prometheus_text(const MetricsInput& in);

/// "# HELP name help" and "# TYPE name type" lines, for families written elsewhere.
void append_family(std::string& out, const char* name, const char* type, const char* help);

/// A counter family by reason: `name`{reason="…"} for each (reason, count), zeros included.
void append_reason_counts(std::string& out, const char* name, const char* help,
                          const std::vector<std::pair<std::string, uint64_t>>& counts);

/// A sample value that round-trips (%.17g).
std::string metric_number(double v);

/// A label value with \, " and newline escaped as the format requires.
std::string escape_label_value(const std::string& value);

}  // namespace fq::daemon
