#include "daemon/control/stats_log.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdio>

#include "daemon/control/drop_reasons.h"
#include "daemon/control/late_warning.h"

namespace fq::daemon {

StatsLog::StatsLog(StreamRegistry& registry, double interval_s)
    : registry_(registry), interval_s_(interval_s), thread_([this] { run(); }) {}

StatsLog::~StatsLog() { stop(); }

void StatsLog::stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

std::vector<std::string> StatsLog::lines(const std::vector<StreamSnapshot>& now, double seconds,
                                         std::map<std::string, StreamCounters>& previous) {
  std::vector<std::string> out;
  // Only the streams of this snapshot are kept for the next interval: an expired stream's
  // counters go with it.
  std::map<std::string, StreamCounters> current;
  for (const StreamSnapshot& s : now) {
    auto was = previous.find(s.stream_id);
    const StreamCounters before = was != previous.end() ? was->second : StreamCounters{};
    const StreamCounters& c = s.counters;
    current.emplace(s.stream_id, c);
    if (c.frames_in == before.frames_in) continue;
    auto it = s.stages.find("receive_to_publish");
    const double p99 = it == s.stages.end() ? 0.0 : it->second.p99_ms;
    char line[512];
    std::snprintf(line, sizeof line,
                  "[stats] stream=%s fps=%.1f p99=%.1fms late=%llu superseded=%llu stale=%llu errors=%llu",
                  s.stream_id.c_str(), static_cast<double>(c.frames_out - before.frames_out) / seconds, p99,
                  static_cast<unsigned long long>(c.late - before.late),
                  static_cast<unsigned long long>(c.superseded - before.superseded),
                  static_cast<unsigned long long>(c.dropped_stale - before.dropped_stale),
                  static_cast<unsigned long long>(c.errors - before.errors));
    out.push_back(line);
    for (std::string& d : drop_lines(s.stream_id, c, before)) out.push_back(std::move(d));
  }
  previous.swap(current);
  return out;
}

void StatsLog::run() {
  using clock = std::chrono::steady_clock;
  std::map<std::string, StreamCounters> previous;
  auto last = clock::now();
  std::unique_lock<std::mutex> lock(mutex_);
  while (!wake_.wait_for(lock, std::chrono::duration<double>(interval_s_), [this] { return stopping_; })) {
    const auto now = clock::now();
    std::vector<StreamSnapshot> snaps;
    registry_.snapshot("", snaps);
    const double seconds = std::chrono::duration<double>(now - last).count();
    std::vector<std::string> warnings;  // judged against `previous` before lines() moves it on
    for (const StreamSnapshot& s : snaps) {
      StreamSettings settings;
      if (!registry_.find(s.stream_id, settings)) continue;
      if (auto w = late_warning(s, previous[s.stream_id], seconds, settings.budget_ms))
        warnings.push_back(*w);
    }
    for (const std::string& l : lines(snaps, seconds, previous)) spdlog::info("{}", l);
    for (const std::string& w : warnings) spdlog::warn("{}", w);
    last = now;
  }
}

}  // namespace fq::daemon
