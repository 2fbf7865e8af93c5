#include "daemon/stream/stream_registry.h"

#include <algorithm>

namespace fq::daemon {

StreamRegistry::StreamRegistry(const DaemonConfig& config)
    : config_(config), defaults_(config.defaults), configured_(config.streams) {
  memory_.set_budget(config.caps.memory_budget_mb << 20);
  // Configured streams are listed (and controllable) before their first frame.
  for (const auto& [id, s] : config.streams)
    streams_[id] = std::make_shared<Stream>(id, s, wall_ns(), &memory_);
}

const StreamSettings& StreamRegistry::configured(const std::string& stream_id) const {
  auto it = configured_.find(stream_id);
  return it != configured_.end() ? it->second : defaults_;
}

StreamPtr StreamRegistry::entry(const std::string& stream_id, int64_t now_ns, bool frame) {
  auto it = streams_.find(stream_id);
  if (it != streams_.end()) {
    if (frame) it->second->fed = true;
    return it->second;
  }
  if (streams_.size() >= config_.caps.max_streams) {
    // set_params with create on 8 ids every 0.5 s held every slot (max_streams 8) and a new
    // producer got none of its 75 frames in: a slot no frame has used is the first to go.
    auto idle = streams_.end();
    for (auto c = streams_.begin(); frame && c != streams_.end(); ++c) {
      if (c->second->fed || configured_.contains(c->first)) continue;
      if (idle == streams_.end() || c->second->last_seen_ns.load(std::memory_order_relaxed) <
                                        idle->second->last_seen_ns.load(std::memory_order_relaxed))
        idle = c;
    }
    if (idle == streams_.end()) return nullptr;
    streams_.erase(idle);  // no frame holds it: nothing of it is in flight
  }
  StreamPtr s = std::make_shared<Stream>(stream_id, configured(stream_id), now_ns, &memory_);
  s->fed = frame;
  streams_.emplace(stream_id, s);
  return s;
}

StreamPtr StreamRegistry::admit(const std::string& stream_id, int64_t now_ns) {
  return touch(stream_id, now_ns, true);
}

StreamPtr StreamRegistry::touch(const std::string& stream_id, int64_t now_ns, bool frame) {
  StreamPtr s;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    s = entry(stream_id, now_ns, frame);
  }
  if (s) {
    int64_t seen = s->last_seen_ns.load(std::memory_order_relaxed);
    while (seen < now_ns && !s->last_seen_ns.compare_exchange_weak(seen, now_ns, std::memory_order_relaxed)) {
    }
  }
  return s;
}

StreamPtr StreamRegistry::find(const std::string& stream_id) const {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = streams_.find(stream_id);
  return it == streams_.end() ? nullptr : it->second;
}

bool StreamRegistry::settings(const std::string& stream_id, StreamSettings& out) {
  const StreamPtr s = touch(stream_id, wall_ns(), false);
  if (!s) return false;
  out = s->settings();
  return true;
}

bool StreamRegistry::set_settings(const std::string& stream_id, const StreamSettings& settings) {
  const StreamPtr s = touch(stream_id, wall_ns(), false);
  if (!s) return false;
  s->set_settings(settings);
  return true;
}

bool StreamRegistry::find(const std::string& stream_id, StreamSettings& out) const {
  const StreamPtr s = find(stream_id);
  if (!s) return false;
  out = s->settings();
  return true;
}

void StreamRegistry::reload(const StreamSettings& defaults,
                            const std::map<std::string, StreamSettings>& streams) {
  std::lock_guard<std::mutex> lock(mutex_);
  defaults_ = defaults;
  configured_ = streams;
  const int64_t now = wall_ns();
  for (const auto& [id, s] : configured_) {
    // A stream configured anew is registered like one of the config at start.
    if (!streams_.contains(id)) streams_[id] = std::make_shared<Stream>(id, s, now, &memory_);
  }
  for (auto& [id, s] : streams_) s->set_settings(configured(id));
}

std::vector<std::string> StreamRegistry::expire_idle(int64_t now_ns, double idle_s) {
  std::vector<std::string> gone;
  if (idle_s <= 0) return gone;
  std::vector<StreamPtr> dropped;  // destroyed outside the lock (a label track can be tens of MB)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (auto it = streams_.begin(); it != streams_.end();) {
      const bool pinned = configured_.contains(it->first);
      if (!pinned &&
          double(now_ns - it->second->last_seen_ns.load(std::memory_order_relaxed)) > idle_s * 1e9) {
        gone.push_back(it->first);
        dropped.push_back(std::move(it->second));
        it = streams_.erase(it);
      } else {
        ++it;
      }
    }
  }
  // Their counts stay in /metrics, in the aggregate: the sums over streams never go down.
  std::lock_guard<std::mutex> lock(other_mutex_);
  for (const StreamPtr& s : dropped) s->move_series(other_);
  return gone;
}

bool StreamRegistry::has_own_series(const std::string& id, const Stream& s, int64_t now_ns,
                                    double idle_s) const {
  if (id == kOtherStreams) return false;
  if (configured_.contains(id) || idle_s <= 0) return true;
  return double(now_ns - s.last_seen_ns.load(std::memory_order_relaxed)) <= idle_s * 1e9;
}

void StreamRegistry::metric_series(int64_t now_ns, double idle_s, std::vector<NamedSeries>& named,
                                   MetricSeries& other) {
  std::vector<StreamPtr> own, rest;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& [id, s] : streams_) (has_own_series(id, *s, now_ns, idle_s) ? own : rest).push_back(s);
  }
  for (const StreamPtr& s : own) named.push_back({s->id(), s->own_series()});
  std::lock_guard<std::mutex> lock(other_mutex_);
  for (const StreamPtr& s : rest) s->move_series(other_);
  other = other_;
}

std::vector<std::string> StreamRegistry::own_series_ids(int64_t now_ns, double idle_s) const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<std::string> ids;
  for (const auto& [id, s] : streams_)
    if (has_own_series(id, *s, now_ns, idle_s)) ids.push_back(id);
  return ids;
}

std::vector<std::string> StreamRegistry::list() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<std::string> ids;
  ids.reserve(streams_.size());
  for (const auto& [id, s] : streams_) ids.push_back(id);
  return ids;
}

std::vector<StreamPtr> StreamRegistry::all() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<StreamPtr> out;
  out.reserve(streams_.size());
  for (const auto& [id, s] : streams_) out.push_back(s);
  return out;
}

bool StreamRegistry::snapshot(const std::string& stream_id, std::vector<StreamSnapshot>& out,
                              const std::function<void()>& copied) const {
  std::vector<StreamPtr> streams;
  if (stream_id.empty()) {
    std::lock_guard<std::mutex> lock(mutex_);
    streams.reserve(streams_.size());
    for (const auto& [id, s] : streams_) streams.push_back(s);
  } else if (StreamPtr s = find(stream_id)) {
    streams.push_back(std::move(s));
  } else {
    return false;
  }
  std::vector<StreamSamples> samples;
  samples.reserve(streams.size());
  for (const StreamPtr& s : streams) samples.push_back(s->samples());
  if (copied) copied();
  for (const StreamSamples& s : samples) out.push_back(summarize(s));
  return true;
}

}  // namespace fq::daemon
