#include "daemon/stream/latest_results.h"

#include "daemon/stream/stream_registry.h"

namespace fq::daemon {

void LatestResults::offer(Stream& stream, const wire::ResultHeader& header, const std::vector<std::string>& chunks,
                          const std::vector<uint32_t>& triangles) {
  if (header.status() == wire::ERROR) return;
  LatestSlot& e = stream.latest;
  std::shared_ptr<const std::vector<uint32_t>> faces;
  uint64_t faces_id = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (std::chrono::steady_clock::now() > e.watched_until) return;
    faces = e.faces;
    faces_id = e.faces_id;
  }
  // The copies (and the faces comparison) are made outside the lock: viewers waiting on
  // other streams are not held up.
  auto r = std::make_shared<LatestResult>();
  r->header = header;
  r->chunks = chunks;
  const bool positions = header.form() == wire::POSITIONS;
  if (positions && !(faces && *faces == triangles)) {
    faces = std::make_shared<const std::vector<uint32_t>>(triangles);
    faces_id = 0;  // new faces: a new id, given below
  }
  std::lock_guard<std::mutex> lock(mutex_);
  if (positions) {
    if (faces_id == 0) faces_id = ++faces_ids_;
    e.faces = r->faces = faces;
    e.faces_id = r->faces_id = faces_id;
  }
  r->index = ++e.index;
  e.latest = std::move(r);
  changed_.notify_all();
}

std::shared_ptr<const LatestResult> LatestResults::wait_newer(const std::string& stream, uint64_t after,
                                                              std::chrono::milliseconds timeout) {
  // The viewer's stream is held for the wait: it may expire meanwhile, and is freed after.
  const StreamPtr s = registry_.find(stream);
  if (!s) return nullptr;
  LatestSlot& e = s->latest;
  std::unique_lock<std::mutex> lock(mutex_);
  e.watched_until = std::chrono::steady_clock::now() + std::chrono::seconds(kWatchSeconds);
  changed_.wait_for(lock, timeout, [&] { return closed_ || (e.latest && e.latest->index > after); });
  if (closed_ || !e.latest || e.latest->index <= after) return nullptr;
  return e.latest;
}

void LatestResults::close() {
  std::lock_guard<std::mutex> lock(mutex_);
  closed_ = true;
  changed_.notify_all();
}

}  // namespace fq::daemon
