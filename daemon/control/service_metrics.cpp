#include "daemon/control/service_metrics.h"

#include "common/version.h"
#include "daemon/control/prometheus_text.h"

namespace fq::daemon {
namespace {

std::string label(const char* name, const std::string& value) {
  return std::string(name) + "=\"" + escape_label_value(value) + "\"";
}

void engines(std::string& out, const std::vector<EngineLoad>& list) {
  // Two CPU engines share a name: the index tells them apart.
  const auto labels = [](const EngineLoad& e, size_t i) {
    return "{" + label("engine", e.name) + "," + label("index", std::to_string(i)) + "}";
  };
  append_family(
      out, "fq_engine_busy_seconds_total", "counter",
      "Time each engine spent running frames; its rate is the engine's utilisation (1 = always busy).");
  for (size_t i = 0; i < list.size(); ++i)
    out += "fq_engine_busy_seconds_total" + labels(list[i], i) + " " + metric_number(list[i].busy_seconds) +
           "\n";
  append_family(out, "fq_engine_frames_total", "counter",
                "Frames each engine ran (finished, failed or stopped).");
  for (size_t i = 0; i < list.size(); ++i)
    out += "fq_engine_frames_total" + labels(list[i], i) + " " + std::to_string(list[i].frames) + "\n";
}

}  // namespace

std::string service_metrics_text(const ServiceMetricsInput& in) {
  std::string out;
  append_family(out, "fq_build_info", "gauge",
                "fq's version and whether the CUDA engine is compiled in; always 1.");
  out += "fq_build_info{" + label("version", version_string()) + "," +
         label("cuda", built_with_cuda() ? "compiled_in" : "absent") + "} 1\n";
  append_reason_counts(
      out, "fq_refused_total",
      "Ingest and control messages, subscribers and ZeroMQ connections refused before any stream "
      "state was made for them, by reason (bad_stream_id, malformed, not_allowed, "
      "too_many_streams, unauthenticated, oversized, subscriptions).",
      in.refusals);
  append_family(
      out, "fq_ingest_reconnects_total", "counter",
      "Times fqd connected again to an [ingest] connect producer that ZeroMQ had dropped for a protocol "
      "error (a part over caps.max_frame_bytes, a failed CURVE handshake) and would not reconnect.");
  out += "fq_ingest_reconnects_total " + std::to_string(in.ingest_reconnects) + "\n";
  append_family(out, "fq_stream_budget_seconds", "gauge",
                "Each stream's receive-to-publish budget (budget_ms): results later than this are LATE.");
  for (const auto& [stream, ms] : in.budgets_ms)
    out += "fq_stream_budget_seconds{" + label("stream", stream) + "} " + metric_number(ms / 1000.0) + "\n";
  engines(out, in.engines);
  append_family(out, "fq_queue_depth", "gauge",
                "Frames waiting in each pipeline queue: decode, slots (decoded, waiting for an engine), "
                "encode, publish.");
  for (const auto& [queue, n] : in.queues)
    out += "fq_queue_depth{" + label("queue", queue) + "} " + std::to_string(n) + "\n";
  append_family(
      out, "fq_memory_bytes", "gauge",
      "Host bytes fqd keeps per stream, charged to caps.memory_budget_mb, by kind: history (temporal "
      "filtering), label_track (cluster ids), latest (/latest copies), queued (frames from admission "
      "to publish).");
  for (const auto& [kind, bytes] : in.memory)
    out += "fq_memory_bytes{" + label("kind", kind) + "} " + std::to_string(bytes) + "\n";
  append_family(out, "fq_memory_peak_bytes", "gauge",
                "The most host bytes charged to the memory budget at once.");
  out += "fq_memory_peak_bytes " + std::to_string(in.memory_peak) + "\n";
  append_family(out, "fq_memory_budget_bytes", "gauge", "caps.memory_budget_mb in bytes (0: unbounded).");
  out += "fq_memory_budget_bytes " + std::to_string(in.memory_budget) + "\n";
  out += process_metrics_text(in.process);
  return out;
}

}  // namespace fq::daemon
