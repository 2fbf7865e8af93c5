#include "daemon/pipeline/memory_shed.h"

#include <algorithm>
#include <mutex>
#include <utility>
#include <vector>

#include "daemon/stream/stream_history.h"

namespace fq::daemon {

void shed_memory(StreamRegistry& registry, LatestResults& latest, uint64_t need, Shed upto,
                 const void* keep) {
  if (upto == Shed::kNone) return;
  uint64_t freed = latest.drop_idle(need, keep);
  if (freed >= need || upto != Shed::kHistories) return;
  // By when a frame last used what the stream keeps, read once: it moves meanwhile.
  std::vector<std::pair<int64_t, StreamPtr>> streams;
  for (StreamPtr& s : registry.all())
    if (s.get() != keep) streams.emplace_back(s->kept_ns.load(std::memory_order_relaxed), std::move(s));
  std::sort(streams.begin(), streams.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& [used_ns, s] : streams) {
    if (freed >= need) break;
    uint64_t dropped = 0;
    {
      const std::unique_lock<std::mutex> lock(s->temporal.mutex, std::try_to_lock);
      if (lock.owns_lock() && s->temporal.charge.bytes() > 0) {
        dropped += s->temporal.charge.bytes();
        drop_history(s->temporal);
      }
    }
    {
      const std::unique_lock<std::mutex> lock(s->track.mutex, std::try_to_lock);
      if (lock.owns_lock() && s->track.charge.bytes() > 0) {
        dropped += s->track.charge.bytes();
        s->track.tracker.reset();
        s->track.charge.release();
      }
    }
    if (dropped == 0) continue;
    freed += dropped;
    s->count(&StreamCounters::memory_resets);
  }
}

uint64_t frame_bytes(const FrameJob& f) {
  uint64_t chunks = 0;
  for (const zmq::message_t& c : f.chunks) chunks += c.size();
  const uint64_t vertices = f.mesh.num_vertices() > 0 ? f.mesh.num_vertices() : f.header.vertex_count();
  return chunks + kFrameBytesPerVertex * vertices;
}

bool charge_frame(FrameJob& f) {
  Stream* s = f.stream.get();
  if (!s || f.memory.set(s->memory, MemoryKind::kQueued, frame_bytes(f), Shed::kHistories, s)) return true;
  s->count(&StreamCounters::dropped_memory);
  return false;
}

}  // namespace fq::daemon
