#include "daemon/stream/stream.h"

#include <cstddef>
#include <iterator>
#include <utility>

namespace fq::daemon {

Stream::Stream(std::string id, const StreamSettings& settings, int64_t now_ns)
    : last_seen_ns(now_ns), id_(std::move(id)), settings_(settings) {}

// Out of line: the frames a stream still holds (waiting, held for order) are destroyed here.
Stream::~Stream() = default;

StreamSettings Stream::settings() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return settings_;
}

void Stream::set_settings(const StreamSettings& s) {
  std::lock_guard<std::mutex> lock(mutex_);
  settings_ = s;
}

void Stream::count(Counter c, uint64_t n) {
  // The field of each Counter, in the enum's order.
  static constexpr uint64_t StreamCounters::*kFields[] = {
      &StreamCounters::frames_in,     &StreamCounters::frames_out, &StreamCounters::superseded,
      &StreamCounters::dropped_stale, &StreamCounters::late,       &StreamCounters::errors,
      &StreamCounters::time_limited,  &StreamCounters::subscriber_overflows, &StreamCounters::bad_send_time,
      &StreamCounters::temporal_resets, &StreamCounters::untracked, &StreamCounters::preempted};
  static_assert(std::size(kFields) == static_cast<size_t>(Counter::kPreempted) + 1, "one field per Counter");
  std::lock_guard<std::mutex> lock(mutex_);
  counters_.*kFields[static_cast<size_t>(c)] += n;
}

void Stream::record(const std::string& stage, double ms) {
  std::lock_guard<std::mutex> lock(mutex_);
  metrics_.add(stage, ms);
}

StreamSamples Stream::samples() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return {id_, counters_, metrics_};
}

StreamSnapshot summarize(const StreamSamples& s) {
  return {s.stream_id, s.counters, s.metrics.summary(), s.metrics.histograms()};
}

}  // namespace fq::daemon
