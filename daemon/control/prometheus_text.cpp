#include "daemon/control/prometheus_text.h"

#include <cstdio>

namespace fq::daemon {
namespace {

// Bucket bounds are short decimals and print as such with %g.
std::string bound(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

struct CounterFamily {
  const char* name;
  const char* help;
  uint64_t StreamCounters::*field;
};

constexpr CounterFamily kCounters[] = {
    {"fq_frames_in_total", "Frames received (ingest messages attributed to the stream).",
     &StreamCounters::frames_in},
    {"fq_frames_out_total", "Results published with status OK or LATE.", &StreamCounters::frames_out},
    {"fq_superseded_total", "Frames replaced by a newer frame of their stream before an engine took them.",
     &StreamCounters::superseded},
    {"fq_dropped_stale_total",
     "Frames dropped because they were older than the budget when a worker was free.",
     &StreamCounters::dropped_stale},
    {"fq_late_total", "Results published after the stream's budget (also in fq_frames_out_total).",
     &StreamCounters::late},
    {"fq_errors_total", "Error results published (bad input, invalid parameters, engine failure).",
     &StreamCounters::errors},
    {"fq_time_limited_total", "Frames stopped at the engine time limit (also in fq_errors_total).",
     &StreamCounters::time_limited},
    {"fq_subscriber_overflows_total", "Times a subscriber's queue was full and it started missing results.",
     &StreamCounters::subscriber_overflows},
    {"fq_bad_send_time_total",
     "Results whose producer send time was over an hour before publish or after it (left out of "
     "send_to_publish).",
     &StreamCounters::bad_send_time},
    {"fq_temporal_resets_total",
     "Scene cuts of a stream filtered across frames: its temporal history restarted.",
     &StreamCounters::temporal_resets},
    {"fq_untracked_total",
     "Results published with the engine's cluster numbering because id tracking passed the time limit or fqd "
     "was "
     "stopping.",
     &StreamCounters::untracked},
    {"fq_preempted_total",
     "Frames stopped on the engine, unable to meet their budget, so that a lighter stream's frame could "
     "meet its own (not in fq_errors_total).",
     &StreamCounters::preempted},
    {"fq_refused_frames_total",
     "Frames under the stream's id from a producer without CURVE that failed to decode: dropped unanswered, "
     "not "
     "errors (also in fq_refused_total{reason=\"undecodable\"}).",
     &StreamCounters::refused},
    {"fq_memory_resets_total",
     "Times the stream's temporal history or cluster id track was dropped to stay within "
     "caps.memory_budget_mb (its next frame ran alone).",
     &StreamCounters::memory_resets},
    {"fq_dropped_memory_total",
     "Frames dropped without a result because they did not fit caps.memory_budget_mb once nothing else "
     "could be freed.",
     &StreamCounters::dropped_memory},
};

// Each stream with series of its own, then stream="other".
template <class F>
void each_series(const MetricsInput& in, F f) {
  for (const NamedSeries& s : in.series) f(s.stream_id, s.series);
  f(std::string(kOtherStreams), in.other);
}

void histograms(std::string& out, const MetricsInput& in) {
  append_family(out, "fq_stage_latency_seconds", "histogram",
                "Time per pipeline stage (decode, wait, engine, engine.<pass>, encode, receive_to_publish, "
                "send_to_publish) of published results.");
  each_series(in, [&](const std::string& stream, const MetricSeries& s) {
    for (const auto& [stage, h] : s.histograms) {
      const std::string labels =
          "stream=\"" + escape_label_value(stream) + "\",stage=\"" + escape_label_value(stage) + "\"";
      for (size_t i = 0; i < LatencyHistogram::kBoundsMs.size(); ++i)
        out += "fq_stage_latency_seconds_bucket{" + labels + ",le=\"" +
               bound(LatencyHistogram::kBoundsMs[i] / 1000.0) + "\"} " + std::to_string(h.bucket(i)) + "\n";
      out += "fq_stage_latency_seconds_bucket{" + labels + ",le=\"+Inf\"} " + std::to_string(h.count()) + "\n";
      out += "fq_stage_latency_seconds_sum{" + labels + "} " + metric_number(h.sum_ms() / 1000.0) + "\n";
      out += "fq_stage_latency_seconds_count{" + labels + "} " + std::to_string(h.count()) + "\n";
    }
  });
}

void engines_and_gpus(std::string& out, const MetricsInput& in) {
  append_family(out, "fq_engine_info", "gauge",
                "One series per engine; kind is cpu or cuda, index tells engines of one name apart.");
  for (size_t i = 0; i < in.engines.size(); ++i) {
    const std::string& e = in.engines[i];
    const std::string kind = e.rfind("cuda", 0) == 0 ? "cuda" : "cpu";
    out += "fq_engine_info{engine=\"" + escape_label_value(e) + "\",index=\"" + std::to_string(i) + "\",kind=\"" +
           kind + "\"} 1\n";
  }
  append_family(out, "fq_gpu_memory_used_bytes", "gauge",
                "Device memory in use on each GPU with an engine (device-wide).");
  for (const GpuMemory& g : in.gpus)
    out += "fq_gpu_memory_used_bytes{gpu=\"" + std::to_string(g.device) + "\"} " + std::to_string(g.used_bytes) + "\n";
  append_family(out, "fq_gpu_memory_total_bytes", "gauge", "Device memory of each GPU with an engine.");
  for (const GpuMemory& g : in.gpus)
    out += "fq_gpu_memory_total_bytes{gpu=\"" + std::to_string(g.device) + "\"} " + std::to_string(g.total_bytes) +
           "\n";
}

}  // namespace

std::string prometheus_text(const MetricsInput& in) {
  std::string out;
  for (const CounterFamily& f : kCounters) {
    append_family(out, f.name, "counter", f.help);
    each_series(in, [&](const std::string& stream, const MetricSeries& s) {
      out += std::string(f.name) + "{stream=\"" + escape_label_value(stream) + "\"} " +
             std::to_string(s.counters.*f.field) + "\n";
    });
  }
  histograms(out, in);
  append_family(out, "fq_streams", "gauge", "Streams fqd knows (configured or seen).");
  out += "fq_streams " + std::to_string(in.streams) + "\n";
  engines_and_gpus(out, in);
  append_reason_counts(out, "fq_http_refused_total", "HTTP requests and connections refused, by reason.",
                       in.http_refusals);
  return out;
}

}  // namespace fq::daemon
