#include "daemon/stream_registry.h"

#include <algorithm>
#include <cstddef>
#include <iterator>

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

void StreamRegistry::count(const std::string& stream_id, Counter c, uint64_t n) {
  std::lock_guard<std::mutex> lock(mutex_);
  Entry* e = existing(stream_id);
  if (!e) return;
  // The field of each Counter, in the enum's order.
  static constexpr uint64_t StreamCounters::*kFields[] = {
      &StreamCounters::frames_in,     &StreamCounters::frames_out, &StreamCounters::superseded,
      &StreamCounters::dropped_stale, &StreamCounters::late,       &StreamCounters::errors,
      &StreamCounters::time_limited,  &StreamCounters::subscriber_overflows, &StreamCounters::bad_send_time,
      &StreamCounters::untracked,     &StreamCounters::preempted};
  static_assert(std::size(kFields) == static_cast<size_t>(Counter::kPreempted) + 1, "one field per Counter");
  e->counters.*kFields[static_cast<size_t>(c)] += n;
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

StreamSnapshot StreamRegistry::snapshot_of(const std::string& id, const Entry& e) const {
  return {id, e.counters, e.metrics.summary(), e.metrics.histograms()};
}

bool StreamRegistry::snapshot(const std::string& stream_id, std::vector<StreamSnapshot>& out) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (stream_id.empty()) {
    for (const auto& [id, e] : streams_) out.push_back(snapshot_of(id, e));
    return true;
  }
  auto it = streams_.find(stream_id);
  if (it == streams_.end()) return false;
  out.push_back(snapshot_of(stream_id, it->second));
  return true;
}

}  // namespace fq::daemon
