#include "daemon/stream/stream.h"

#include <cstddef>
#include <iterator>
#include <utility>

namespace fq::daemon {

Stream::Stream(std::string id, const StreamSettings& settings, int64_t now_ns, MemoryAccount* memory)
    : last_seen_ns(now_ns), memory(memory), id_(std::move(id)), settings_(settings) {}

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
  std::lock_guard<std::mutex> lock(mutex_);
  counters_.*c += n;
}

void Stream::record(const std::string& stage, double ms) {
  std::lock_guard<std::mutex> lock(mutex_);
  metrics_.add(stage, ms);
}

StreamSamples Stream::samples() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return {id_, counters_, metrics_};
}

MetricSeries Stream::own_series() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return MetricSeries{counters_, metrics_.histograms()}.since(moved_);
}

void Stream::move_series(MetricSeries& other) {
  std::lock_guard<std::mutex> lock(mutex_);
  MetricSeries now{counters_, metrics_.histograms()};
  other.add(now.since(moved_));
  moved_ = std::move(now);
}

StreamSnapshot summarize(const StreamSamples& s) {
  return {s.stream_id, s.counters, s.metrics.summary(), s.metrics.histograms()};
}

}  // namespace fq::daemon
