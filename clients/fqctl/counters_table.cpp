#include "clients/fqctl/counters_table.h"

#include <cstdio>

namespace fq::client {
namespace {

// Stages shown, in pipeline order; "e2e" is fqd's receive -> publish.
constexpr std::pair<const char*, const char*> kStages[] = {
    {"e2e", "receive_to_publish"}, {"decode", "decode"}, {"wait", "wait"}, {"engine", "engine"}, {"encode", "encode"}};

std::string p50_p99(const wire::StreamCounters& c, const char* stage) {
  for (const wire::StagePercentiles& s : c.stages())
    if (s.name() == stage) {
      char buf[48];
      std::snprintf(buf, sizeof buf, "%.1f/%.1f", s.p50_ms(), s.p99_ms());
      return buf;
    }
  return "-";
}

}  // namespace

std::string counters_table(const wire::ControlReply& reply, double seconds, OutCounts& previous) {
  char line[512];
  std::snprintf(line, sizeof line, "%-16s %7s %9s %9s", "stream", "fps", "in", "out");
  std::string out = line;
  for (const auto& [title, stage] : kStages) {
    std::snprintf(line, sizeof line, " %13s", (std::string(title) + " p50/p99").c_str());
    out += line;
  }
  out += "  superseded    stale     late   errors\n";
  for (const wire::StreamCounters& c : reply.counters()) {
    std::string fps = "-";
    if (auto it = previous.find(c.stream_id()); it != previous.end() && seconds > 0) {
      std::snprintf(line, sizeof line, "%.1f", static_cast<double>(c.frames_out() - it->second) / seconds);
      fps = line;
    }
    previous[c.stream_id()] = c.frames_out();
    std::snprintf(line, sizeof line, "%-16s %7s %9llu %9llu", c.stream_id().c_str(), fps.c_str(),
                  static_cast<unsigned long long>(c.frames_in()), static_cast<unsigned long long>(c.frames_out()));
    out += line;
    for (const auto& [title, stage] : kStages) {
      std::snprintf(line, sizeof line, " %13s", p50_p99(c, stage).c_str());
      out += line;
    }
    std::snprintf(line, sizeof line, "  %10llu %8llu %8llu %8llu\n", static_cast<unsigned long long>(c.superseded()),
                  static_cast<unsigned long long>(c.dropped_stale()), static_cast<unsigned long long>(c.late()),
                  static_cast<unsigned long long>(c.errors()));
    out += line;
  }
  if (reply.counters_size() == 0) out += "(no streams yet)\n";
  out += "latencies in ms over each stream's last 2048 frames; fps = results per second since the last refresh\n";
  return out;
}

}  // namespace fq::client
