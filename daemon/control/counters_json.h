// The JSON form of fqd's per-stream counters, shared by `fqctl counters --json` and fqd's
// `GET /streams`: the same words as the Prometheus metrics (`"frames_in": N` is
// `fq_frames_in_total{stream="…"}`), so a script can switch between them.
#pragma once

#include <nlohmann/json.hpp>

#include "wire/fq.pb.h"

namespace fq::daemon {

/// One stream: {"stream", a key per counter (FQ_STREAM_COUNTERS, daemon/stream/stream_counters.h),
/// "stages": {name: {"p50_ms", "p95_ms", "p99_ms", "count"}}}.
nlohmann::json counters_json(const wire::StreamCounters& c);

/// {"streams": [counters_json of each]}.
nlohmann::json counters_json(const wire::ControlReply& reply);

}  // namespace fq::daemon
