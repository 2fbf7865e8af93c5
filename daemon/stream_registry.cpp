#include "daemon/stream_registry.h"

#include <algorithm>
#include <cstddef>
#include <iterator>
#include <utility>

namespace fq::daemon {

StreamRegistry::StreamRegistry(const DaemonConfig& config)
    : config_(config), defaults_(config.defaults), configured_(config.streams) {
  // Configured streams are listed (and controllable) before their first frame.
  for (const auto& [id, s] : config.streams) {
    streams_[id].settings = s;
    streams_[id].pinned = true;
  }
}

StreamRegistry::Entry* StreamRegistry::existing(const std::string& stream_id) {
  auto it = streams_.find(stream_id);
  return it == streams_.end() ? nullptr : &it->second;
}

StreamRegistry::Entry* StreamRegistry::entry(const std::string& stream_id) {
  auto it = streams_.find(stream_id);
  if (it != streams_.end()) return &it->second;
  if (streams_.size() >= config_.caps.max_streams) return nullptr;
  Entry& e = streams_[stream_id];
  e.settings = configured(stream_id);
  return &e;
}

const StreamSettings& StreamRegistry::configured(const std::string& stream_id) const {
  auto it = configured_.find(stream_id);
  return it != configured_.end() ? it->second : defaults_;
}

void StreamRegistry::reload(const StreamSettings& defaults, const std::map<std::string, StreamSettings>& streams) {
  std::lock_guard<std::mutex> lock(mutex_);
  defaults_ = defaults;
  configured_ = streams;
  for (const auto& [id, s] : configured_) streams_[id].pinned = true;
  for (auto& [id, e] : streams_) e.settings = configured(id);
}

bool StreamRegistry::settings(const std::string& stream_id, StreamSettings& out, int64_t now_ns) {
  std::lock_guard<std::mutex> lock(mutex_);
  Entry* e = entry(stream_id);
  if (!e) return false;
  e->last_seen_ns = std::max(e->last_seen_ns, now_ns);
  out = e->settings;
  return true;
}

std::vector<std::string> StreamRegistry::expire_idle(int64_t now_ns, double idle_s) {
  std::vector<std::string> gone;
  if (idle_s <= 0) return gone;
  std::lock_guard<std::mutex> lock(mutex_);
  for (auto it = streams_.begin(); it != streams_.end();) {
    const Entry& e = it->second;
    if (!e.pinned && double(now_ns - e.last_seen_ns) > idle_s * 1e9) {
      gone.push_back(it->first);
      it = streams_.erase(it);
    } else {
      ++it;
    }
  }
  return gone;
}

bool StreamRegistry::set_settings(const std::string& stream_id, const StreamSettings& s) {
  std::lock_guard<std::mutex> lock(mutex_);
  Entry* e = entry(stream_id);
  if (!e) return false;
  e->settings = s;
  e->pinned = true;
  return true;
}

bool StreamRegistry::find(const std::string& stream_id, StreamSettings& out) const {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = streams_.find(stream_id);
  if (it == streams_.end()) return false;
  out = it->second.settings;
  return true;
}

namespace {

// The field of each Counter, in the enum's order.
constexpr uint64_t StreamCounters::*kCounterFields[] = {
    &StreamCounters::frames_in,     &StreamCounters::frames_out, &StreamCounters::superseded,
    &StreamCounters::dropped_stale, &StreamCounters::late,       &StreamCounters::errors,
    &StreamCounters::time_limited,  &StreamCounters::subscriber_overflows, &StreamCounters::bad_send_time};
static_assert(std::size(kCounterFields) == static_cast<size_t>(Counter::kBadSendTime) + 1, "one field per Counter");

uint64_t& field(StreamCounters& c, Counter which) { return c.*kCounterFields[static_cast<size_t>(which)]; }

}  // namespace

void StreamRegistry::count(const std::string& stream_id, Counter c, uint64_t n) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (Entry* e = existing(stream_id)) field(e->counters, c) += n;
}

void StreamRegistry::record_result(const std::string& stream_id, std::span<const Counter> counters,
                                   std::span<const StageSample> samples) {
  std::lock_guard<std::mutex> lock(mutex_);
  Entry* e = existing(stream_id);
  if (!e) return;
  for (const Counter c : counters) ++field(e->counters, c);
  for (const StageSample& s : samples) e->metrics.add(*s.stage, s.ms);
}

void StreamRegistry::record(const std::string& stream_id, const std::string& stage, double ms) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (Entry* e = existing(stream_id)) e->metrics.add(stage, ms);
}

std::vector<std::string> StreamRegistry::list() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<std::string> ids;
  for (const auto& [id, e] : streams_) ids.push_back(id);
  return ids;
}

bool StreamRegistry::snapshot(const std::string& stream_id, std::vector<StreamSnapshot>& out) const {
  // Stream by stream, the samples are copied under the lock and summarised outside it: the
  // publisher takes this lock for every result, and the percentiles of many streams' windows
  // take milliseconds. The lock is held for one stream's memory copy at a time.
  const std::vector<std::string> ids = stream_id.empty() ? list() : std::vector<std::string>{stream_id};
  SampleCopy samples;
  for (const std::string& id : ids) {
    StreamSnapshot snap{id, {}, {}, {}};
    {
      std::lock_guard<std::mutex> lock(mutex_);
      auto it = streams_.find(id);
      if (it == streams_.end()) {
        if (!stream_id.empty()) return false;
        continue;  // expired since the list was taken
      }
      snap.counters = it->second.counters;
      snap.histograms = it->second.metrics.histograms();
      it->second.metrics.copy_samples(samples);
    }
    snap.stages = samples.summary();
    out.push_back(std::move(snap));
  }
  return true;
}

}  // namespace fq::daemon
