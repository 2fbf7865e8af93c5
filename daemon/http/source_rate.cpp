#include "daemon/http/source_rate.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iterator>

namespace fq::daemon {

void SourceRate::refill(Bucket& b, int64_t now_ns) const {
  if (now_ns > b.at_ns) b.tokens = std::min(burst_, b.tokens + double(now_ns - b.at_ns) * 1e-9 * per_second_);
  b.at_ns = std::max(b.at_ns, now_ns);
}

SourceRate::Bucket& SourceRate::bucket_of(const std::string& source, int64_t now_ns) {
  if (auto it = buckets_.find(source); it != buckets_.end()) return it->second;
  if (buckets_.size() >= max_sources_) {
    for (auto it = buckets_.begin(); it != buckets_.end();) {
      refill(it->second, now_ns);
      it = it->second.tokens >= burst_ ? buckets_.erase(it) : std::next(it);
    }
  }
  if (buckets_.size() >= max_sources_) {
    if (!shared_started_) shared_ = {burst_, now_ns};
    shared_started_ = true;
    return shared_;
  }
  return buckets_.emplace(source, Bucket{burst_, now_ns}).first->second;
}

bool SourceRate::allow(const std::string& source, int64_t now_ns, int& retry_after_s) {
  std::lock_guard<std::mutex> lock(mutex_);
  Bucket& b = bucket_of(source, now_ns);
  refill(b, now_ns);
  if (b.tokens >= 1.0) {
    b.tokens -= 1.0;
    return true;
  }
  retry_after_s = std::max(1, static_cast<int>(std::ceil((1.0 - b.tokens) / per_second_)));
  return false;
}

bool SourceRate::allow_now(const std::string& source, int& retry_after_s) {
  const int64_t now = std::chrono::duration_cast<std::chrono::nanoseconds>(
                          std::chrono::steady_clock::now().time_since_epoch())
                          .count();
  return allow(source, now, retry_after_s);
}

size_t SourceRate::sources() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return buckets_.size();
}

}  // namespace fq::daemon
