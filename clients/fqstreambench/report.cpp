#include "clients/fqstreambench/report.h"

#include <algorithm>
#include <cstdio>

namespace fq::bench {
namespace {

// fqd's counter deltas over the run, summed over the benchmark's streams.
struct Deltas {
  uint64_t in = 0, out = 0, superseded = 0, stale = 0, late = 0, errors = 0;
};

Deltas deltas(const RunInfo& r) {
  Deltas d;
  for (const auto& [id, a] : r.after) {
    if (!r.sent.count(id)) continue;
    const wire::StreamCounters b = r.before.count(id) ? r.before.at(id) : wire::StreamCounters{};
    d.in += a.frames_in() - b.frames_in();
    d.out += a.frames_out() - b.frames_out();
    d.superseded += a.superseded() - b.superseded();
    d.stale += a.dropped_stale() - b.dropped_stale();
    d.late += a.late() - b.late();
    d.errors += a.errors() - b.errors();
  }
  return d;
}

uint64_t total(const std::map<std::string, uint64_t>& m) {
  uint64_t t = 0;
  for (const auto& [k, v] : m) t += v;
  return t;
}

std::string triple(const nlohmann::json& s) {
  char b[96];
  std::snprintf(b, sizeof b, "%.1f / %.1f / %.1f", s.value("p50_ms", 0.0), s.value("p95_ms", 0.0),
                s.value("p99_ms", 0.0));
  return b;
}

double achieved_fps(const RunInfo& r) {
  const double measured = r.seconds - r.warmup;
  return measured > 0 ? static_cast<double>(r.overall.results() - r.overall.errors()) / measured / r.streams
                      : 0.0;
}

// fqd's CPU per published frame, by stage, beside the floor; "other" is what fqd's threads
// used outside the stages (ZeroMQ I/O threads, queue hand-offs, the control socket).
void add_cpu(const RunInfo& r, const Deltas& d, nlohmann::json& fqd) {
  if (!r.cpu.measured || d.out == 0) return;
  const double per_frame = 1e3 / static_cast<double>(d.out);
  nlohmann::json stages = nlohmann::json::object();
  double staged = 0;
  for (const auto& [name, s] : r.cpu.stage_seconds) {
    stages[name] = s * per_frame;
    staged += s;
  }
  stages["other"] = std::max(0.0, r.cpu.threads_seconds - staged) * per_frame;
  const double cpu = r.cpu.threads_seconds * per_frame;
  const double floor = r.cpu.floor_decode_ms + r.cpu.floor_encode_ms;
  fqd["cpu_ms_per_frame"] = cpu;
  fqd["stage_cpu_ms_per_frame"] = stages;
  if (r.cpu.floor_decode_ms >= 0 && r.cpu.floor_encode_ms >= 0) {
    fqd["floor_cpu_ms_per_frame"] = floor;
    fqd["floor_decode_cpu_ms"] = r.cpu.floor_decode_ms;
    fqd["floor_encode_cpu_ms"] = r.cpu.floor_encode_ms;
    fqd["cpu_over_floor"] = floor > 0 ? cpu / floor : 0.0;
  }
}

nlohmann::json host_json(const HostQuiet& h) {
  nlohmann::json j = {
      {"wakeups", h.wakeups},
      {"wakeup_late_ms", {{"p50", h.late_p50_ms}, {"p99", h.late_p99_ms}, {"max", h.late_max_ms}}},
      {"wakeups_late_over_5ms", h.late_over_5ms}};
  if (h.steal_share >= 0) j["steal_share"] = h.steal_share;
  return j;
}

}  // namespace

nlohmann::json report_json(const RunInfo& r) {
  const Deltas d = deltas(r);
  nlohmann::json streams = nlohmann::json::object();
  for (const auto& [id, s] : r.per_stream) streams[id] = s.to_json();
  const uint64_t measured = total(r.sent_measured);
  nlohmann::json fqd = {{"frames_in", d.in},        {"frames_out", d.out}, {"superseded", d.superseded},
                        {"dropped_stale", d.stale}, {"late", d.late},      {"errors", d.errors}};
  add_cpu(r, d, fqd);
  nlohmann::json bench = nlohmann::json::object();
  if (r.cpu.measured && total(r.sent) > 0) {
    bench["producers_cpu_ms_per_frame"] = r.cpu.producers_ms / static_cast<double>(total(r.sent));
    bench["collector_cpu_ms_per_frame"] = r.cpu.collector_ms / static_cast<double>(total(r.sent));
  }
  return {{"mesh", r.mesh_name},
          {"vertices", r.vertices},
          {"triangles", r.triangles},
          {"engine", r.engine},
          {"streams", r.streams},
          {"fps_target", r.fps},
          {"seconds", r.seconds},
          {"warmup", r.warmup},
          {"chunks", r.chunks},
          {"phases", r.phases},
          {"compute", r.compute},
          {"result_form", r.result_form},
          {"frames_sent", total(r.sent)},
          {"frames_sent_measured", measured},
          {"achieved_fps_per_stream", achieved_fps(r)},
          {"drops_measured", measured > r.overall.results() ? measured - r.overall.results() : 0},
          {"fqd", fqd},
          {"bench", bench},
          {"host", host_json(r.host)},
          {"overall", r.overall.to_json()},
          {"per_stream", streams}};
}

std::string report_text(const RunInfo& r) {
  const nlohmann::json j = report_json(r);
  const nlohmann::json& o = j["overall"];
  std::string s;
  char b[512];
  std::snprintf(
      b, sizeof b,
      "fqstreambench: %s (%u V, %u F), %d stream(s) x %.1f fps for %.1f s (first %.1f s not measured), "
      "%u chunk(s), %s phases, engine %s, compute %s, %s results\n",
      r.mesh_name.c_str(), r.vertices, r.triangles, r.streams, r.fps, r.seconds, r.warmup, r.chunks,
      r.phases.c_str(), r.engine.c_str(), r.compute.c_str(), r.result_form.c_str());
  s += b;
  std::snprintf(b, sizeof b,
                "  sent %llu (measured %llu), results measured %llu, achieved %.2f fps/stream, drops %llu "
                "(fqd: superseded %llu, stale %llu), late %llu, errors %llu\n",
                static_cast<unsigned long long>(j["frames_sent"].get<uint64_t>()),
                static_cast<unsigned long long>(j["frames_sent_measured"].get<uint64_t>()),
                static_cast<unsigned long long>(o["results"].get<uint64_t>()),
                j["achieved_fps_per_stream"].get<double>(),
                static_cast<unsigned long long>(j["drops_measured"].get<uint64_t>()),
                static_cast<unsigned long long>(j["fqd"]["superseded"].get<uint64_t>()),
                static_cast<unsigned long long>(j["fqd"]["dropped_stale"].get<uint64_t>()),
                static_cast<unsigned long long>(o["late"].get<uint64_t>()),
                static_cast<unsigned long long>(o["errors"].get<uint64_t>()));
  s += b;
  s += "  receive->publish p50/p95/p99 ms: " + triple(o["receive_to_publish"]) + "\n";
  s += "  send->receive    p50/p95/p99 ms: " + triple(o["send_to_receive"]) + "\n";
  if (j["fqd"].contains("cpu_ms_per_frame")) {
    const nlohmann::json& f = j["fqd"];
    std::snprintf(b, sizeof b, "  fqd CPU per frame: %.2f ms", f["cpu_ms_per_frame"].get<double>());
    s += b;
    if (f.contains("floor_cpu_ms_per_frame")) {
      std::snprintf(b, sizeof b, " = %.2f x the floor (plain Draco decode %.2f + encode %.2f ms)",
                    f["cpu_over_floor"].get<double>(), f["floor_decode_cpu_ms"].get<double>(),
                    f["floor_encode_cpu_ms"].get<double>());
      s += b;
    }
    s += "\n   ";
    for (const auto& [name, ms] : f["stage_cpu_ms_per_frame"].items()) {
      std::snprintf(b, sizeof b, " %s %.2f", name.c_str(), ms.get<double>());
      s += b;
    }
    s += "\n";
  }
  const nlohmann::json& h = j["host"];
  std::snprintf(b, sizeof b, "  host: 1 ms sleeps woke p50/p99/max %.2f/%.2f/%.1f ms late, %llu over 5 ms",
                h["wakeup_late_ms"]["p50"].get<double>(), h["wakeup_late_ms"]["p99"].get<double>(),
                h["wakeup_late_ms"]["max"].get<double>(),
                static_cast<unsigned long long>(h["wakeups_late_over_5ms"].get<uint64_t>()));
  s += b;
  if (h.contains("steal_share")) {
    std::snprintf(b, sizeof b, "; steal %.2f %%", 100 * h["steal_share"].get<double>());
    s += b;
  }
  s += "\n";
  s += "  stages p50/p95/p99 ms:\n";
  for (const auto& [name, st] : o["stages"].items()) s += "    " + name + ": " + triple(st) + "\n";
  return s;
}

std::string report_markdown_header() {
  return "| mesh | V | streams × fps | chunks | engine | achieved fps/stream | recv→pub p50 / p95 / p99 ms | "
         "send→recv p50 / p95 / p99 ms | drops (superseded, stale) | late |\n"
         "|---|---:|---|---:|---|---:|---|---|---|---:|";
}

std::string report_markdown_row(const RunInfo& r) {
  const nlohmann::json j = report_json(r);
  const nlohmann::json& o = j["overall"];
  char b[512];
  std::snprintf(b, sizeof b, "| %s | %u | %d × %.0f | %u | %s | %.1f | %s | %s | %llu (%llu, %llu) | %llu |",
                r.mesh_name.c_str(), r.vertices, r.streams, r.fps, r.chunks, r.engine.c_str(),
                j["achieved_fps_per_stream"].get<double>(), triple(o["receive_to_publish"]).c_str(),
                triple(o["send_to_receive"]).c_str(),
                static_cast<unsigned long long>(j["drops_measured"].get<uint64_t>()),
                static_cast<unsigned long long>(j["fqd"]["superseded"].get<uint64_t>()),
                static_cast<unsigned long long>(j["fqd"]["dropped_stale"].get<uint64_t>()),
                static_cast<unsigned long long>(o["late"].get<uint64_t>()));
  return b;
}

}  // namespace fq::bench
