#include "clients/fqctl/counters_table.h"

#include <cstdio>

namespace fq::client {
namespace {

// Stages shown, in pipeline order; "e2e" is fqd's receive -> publish.
constexpr std::pair<const char*, const char*> kStages[] = {{"e2e", "receive_to_publish"},
                                                           {"decode", "decode"},
                                                           {"wait", "wait"},
                                                           {"engine", "engine"},
                                                           {"encode", "encode"}};

// Stream ids longer than the first column are cut, ending in '~', so that every line fits
// 80 columns (the full ids: fqctl streams, or --json).
constexpr size_t kIdWidth = 12;

std::string short_id(const std::string& id) {
  return id.size() <= kIdWidth ? id : id.substr(0, kIdWidth - 1) + "~";
}

std::string p50_p99(const wire::StreamCounters& c, const char* stage) {
  for (const wire::StagePercentiles& s : c.stages())
    if (s.name() == stage) {
      char buf[48];
      std::snprintf(buf, sizeof buf, "%.1f/%.1f", s.p50_ms(), s.p99_ms());
      return buf;
    }
  return "-";
}

unsigned long long u(uint64_t v) { return static_cast<unsigned long long>(v); }

}  // namespace

std::string counters_table(const wire::ControlReply& reply, double seconds, OutCounts& previous) {
  char line[256];
  std::snprintf(line, sizeof line, "%-12s %6s %8s %8s %10s %7s %7s %7s\n", "stream", "fps", "in", "out",
                "superseded", "stale", "late", "errors");
  std::string frames = line;
  std::snprintf(line, sizeof line, "%-12s", "p50/p99 ms");
  std::string stages = line;
  for (const auto& [title, stage] : kStages) {
    std::snprintf(line, sizeof line, " %12s", title);
    stages += line;
  }
  stages += "\n";
  for (const wire::StreamCounters& c : reply.counters()) {
    std::string fps = "-";
    if (auto it = previous.find(c.stream_id()); it != previous.end() && seconds > 0) {
      std::snprintf(line, sizeof line, "%.1f", static_cast<double>(c.frames_out() - it->second) / seconds);
      fps = line;
    }
    previous[c.stream_id()] = c.frames_out();
    const std::string id = short_id(c.stream_id());
    std::snprintf(line, sizeof line, "%-12s %6s %8llu %8llu %10llu %7llu %7llu %7llu\n", id.c_str(),
                  fps.c_str(), u(c.frames_in()), u(c.frames_out()), u(c.superseded()), u(c.dropped_stale()),
                  u(c.late()), u(c.errors()));
    frames += line;
    std::snprintf(line, sizeof line, "%-12s", id.c_str());
    stages += line;
    for (const auto& [title, stage] : kStages) {
      std::snprintf(line, sizeof line, " %12s", p50_p99(c, stage).c_str());
      stages += line;
    }
    stages += "\n";
  }
  if (reply.counters_size() == 0) return frames + "(no streams yet)\n";
  return frames + "\n" + stages +
         "latencies over each stream's last 2048 frames; fps: results per second\n"
         "since the last refresh\n";
}

}  // namespace fq::client
