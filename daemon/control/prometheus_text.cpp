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
      out +=
          "fq_stage_latency_seconds_bucket{" + labels + ",le=\"+Inf\"} " + std::to_string(h.count()) + "\n";
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
    out += "fq_engine_info{engine=\"" + escape_label_value(e) + "\",index=\"" + std::to_string(i) +
           "\",kind=\"" + kind + "\"} 1\n";
  }
  append_family(out, "fq_gpu_memory_used_bytes", "gauge",
                "Device memory in use on each GPU with an engine (device-wide).");
  for (const GpuMemory& g : in.gpus)
    out += "fq_gpu_memory_used_bytes{gpu=\"" + std::to_string(g.device) + "\"} " +
           std::to_string(g.used_bytes) + "\n";
  append_family(out, "fq_gpu_memory_total_bytes", "gauge", "Device memory of each GPU with an engine.");
  for (const GpuMemory& g : in.gpus)
    out += "fq_gpu_memory_total_bytes{gpu=\"" + std::to_string(g.device) + "\"} " +
           std::to_string(g.total_bytes) + "\n";
}

}  // namespace

std::string prometheus_text(const MetricsInput& in) {
  std::string out;
  for (const CounterRow& c : kCounterRows) {
    append_family(out, c.metric, c.type, c.help);
    each_series(in, [&](const std::string& stream, const MetricSeries& s) {
      out += std::string(c.metric) + "{stream=\"" + escape_label_value(stream) + "\"} " +
             std::to_string(s.counters.*c.field) + "\n";
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
