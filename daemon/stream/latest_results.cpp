#include "daemon/stream/latest_results.h"

#include <algorithm>
#include <utility>

#include "daemon/stream/stream_registry.h"

namespace fq::daemon {

void LatestResults::offer(Stream& stream, const wire::ResultHeader& header,
                          const std::vector<std::string>& chunks, const std::vector<uint32_t>& triangles) {
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
  // Charged before the lock is taken (making room takes it); the slot's old charge is
  // credited once the lock is released.
  uint64_t bytes = positions ? faces->size() * sizeof(uint32_t) : 0;
  for (const std::string& c : chunks) bytes += c.size();
  MemoryCharge charge;
  if (!charge.set(stream.memory, MemoryKind::kLatest, bytes, Shed::kIdleLatest, &stream)) return;
  std::lock_guard<std::mutex> lock(mutex_);
  std::swap(e.charge, charge);
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

uint64_t LatestResults::drop_idle(uint64_t need, const void* keep) {
  const std::vector<StreamPtr> streams = registry_.all();
  const auto now = std::chrono::steady_clock::now();
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<LatestSlot*> idle;
  for (const StreamPtr& s : streams)
    if (s.get() != keep && s->latest.latest && now > s->latest.watched_until) idle.push_back(&s->latest);
  std::sort(idle.begin(), idle.end(),
            [](const LatestSlot* a, const LatestSlot* b) { return a->watched_until < b->watched_until; });
  uint64_t freed = 0;
  for (LatestSlot* e : idle) {
    if (freed >= need) break;
    freed += e->charge.bytes();
    e->latest.reset();
    e->faces.reset();
    e->charge.release();
  }
  return freed;
}

void LatestResults::close() {
  std::lock_guard<std::mutex> lock(mutex_);
  closed_ = true;
  changed_.notify_all();
}

}  // namespace fq::daemon
