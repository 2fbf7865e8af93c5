#include "daemon/pipeline/decode_queue.h"

#include <algorithm>
#include <chrono>
#include <limits>

namespace fq::daemon {

uint64_t DecodeQueue::bytes_of(const FrameJob& f) {
  uint64_t n = 0;
  for (const zmq::message_t& c : f.chunks) n += c.size();
  return n;
}

namespace {
int64_t steady_ns() { return std::chrono::steady_clock::now().time_since_epoch().count(); }
}  // namespace

bool DecodeQueue::may_decode(uint64_t bytes) const {
  if (bytes <= kSmallFrameBytes || decoders_ < 2 || small_seen_ns_ == 0) return true;
  const bool small_recently = double(steady_ns() - small_seen_ns_) < kSmallWindowS * 1e9;
  return !small_recently || large_in_decoders_ < decoders_ - 1;
}

void DecodeQueue::set_decoders(int decoders) {
  std::lock_guard<std::mutex> lock(mutex_);
  decoders_ = std::max(1, decoders);
}

void DecodeQueue::decoded(const FrameJob& f) {
  if (!f.large_in_decoder) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    --large_in_decoders_;
  }
  ready_.notify_all();
}

bool DecodeQueue::full(uint64_t more_bytes, size_t more_frames) const {
  return frames_ + more_frames > max_frames_ || bytes_ + more_bytes > max_bytes_;
}

void DecodeQueue::set_bounds(size_t max_frames, uint64_t max_bytes) {
  std::lock_guard<std::mutex> lock(mutex_);
  max_frames_ = std::max<size_t>(1, max_frames);
  max_bytes_ = max_bytes;
}

DecodeQueue::Lane& DecodeQueue::lane_of(int64_t connection) {
  for (Lane& l : lanes_)
    if (l.connection == connection) return l;
  lanes_.push_back(Lane{connection, {}, 0, 0});
  return lanes_.back();
}

void DecodeQueue::erase_empty_lanes() {
  for (size_t i = 0; i < lanes_.size();) {
    if (!lanes_[i].places.empty()) {
      ++i;
      continue;
    }
    lanes_.erase(lanes_.begin() + static_cast<std::ptrdiff_t>(i));
    if (next_ > i) --next_;
  }
  if (next_ >= lanes_.size()) next_ = 0;
}

void DecodeQueue::shed(Lane& lane, FramePtr& incoming, std::vector<FramePtr>& dropped) {
  const uint64_t incoming_bytes = bytes_of(*incoming);
  Lane* heaviest = &lane;
  uint64_t most = lane.bytes + incoming_bytes;
  for (Lane& l : lanes_)
    if (l.bytes > most) {
      heaviest = &l;
      most = l.bytes;
    }
  if (heaviest == &lane) {
    dropped.push_back(std::move(incoming));
    return;
  }
  FramePtr& newest = heaviest->places.back();
  const uint64_t b = bytes_of(*newest);
  heaviest->bytes -= b;
  bytes_ -= b;
  --frames_;
  dropped.push_back(std::move(newest));
  heaviest->places.pop_back();
}

bool DecodeQueue::push(FramePtr f, std::vector<FramePtr>& dropped) {
  const uint64_t bytes = bytes_of(*f);
  {
    std::unique_lock<std::mutex> lock(mutex_);
    if (closed_) return false;
    if (bytes <= kSmallFrameBytes) small_seen_ns_ = steady_ns();
    // Its stream's place, wherever it is: the newer frame takes it (the place is the stream's,
    // not the connection's; a stream sent over two connections keeps its first).
    for (Lane& l : lanes_) {
      const auto place = std::find_if(l.places.begin(), l.places.end(),
                                      [&](const FramePtr& q) { return q->stream_id == f->stream_id; });
      if (place == l.places.end()) continue;
      const uint64_t old = bytes_of(**place);
      l.bytes -= old;
      bytes_ -= old;
      --frames_;
      dropped.push_back(std::move(*place));
      if (!full(bytes, 1)) {
        *place = std::move(f);
        l.bytes += bytes;
        bytes_ += bytes;
        ++frames_;
        lock.unlock();
        ready_.notify_all();
        return true;
      }
      l.places.erase(place);  // a larger frame over the bound: room is made below, at the back
      break;
    }
    if (bytes > max_bytes_) {
      // Over the byte bound: alone, once the queue is empty.
      erase_empty_lanes();  // the decoders never see an empty lane
      empty_.wait(lock, [&] { return closed_ || frames_ == 0; });
      if (closed_) return false;
    }
    const auto own_bytes = [&] {
      for (const Lane& l : lanes_)
        if (l.connection == f->connection) return l.bytes;
      return uint64_t{0};
    };
    while (frames_ > 0 && full(bytes, 1)) {
      // A connection alone in the queue starves nobody by waiting: it is held back (the
      // ingest thread waits, then ZeroMQ's marks), as a single producer of many streams expects.
      if (own_bytes() == bytes_) {
        erase_empty_lanes();  // the decoders never see an empty lane
        room_.wait(lock, [&] { return closed_ || !full(bytes, 1) || own_bytes() != bytes_; });
        if (closed_) return false;
        continue;
      }
      shed(lane_of(f->connection), f, dropped);
      if (!f) {
        erase_empty_lanes();
        return true;
      }
    }
    erase_empty_lanes();
    Lane* lane = &lane_of(f->connection);
    lane->places.push_back(std::move(f));
    lane->bytes += bytes;
    bytes_ += bytes;
    ++frames_;
  }
  ready_.notify_all();  // a waiting decoder may take only some frames (may_decode)
  return true;
}

std::optional<FramePtr> DecodeQueue::pop() {
  std::unique_lock<std::mutex> lock(mutex_);
  const auto eligible = [&](const Lane& l) { return may_decode(bytes_of(*l.places.front())); };
  // Woken by pushes and by decoders that finish; a decoder kept for small frames waits with a
  // timeout too, since the window of small frames closes without an event.
  for (;;) {
    if (frames_ == 0 && closed_) return std::nullopt;
    if (frames_ > 0 && std::any_of(lanes_.begin(), lanes_.end(), eligible)) break;
    if (closed_) {
      // Closing: what is queued is handed out regardless of the decoders kept.
      if (frames_ > 0) break;
      return std::nullopt;
    }
    if (frames_ == 0)
      ready_.wait(lock);
    else
      ready_.wait_for(lock, std::chrono::milliseconds(100));
  }
  // Deficit round robin with the smallest quantum, over the lanes whose first frame may take
  // a decoder: when no lane's credit covers its first frame, every lane earns what the closest
  // one lacks, so the next in turn whose credit then covers its frame is served.
  for (;;) {
    uint64_t lack = std::numeric_limits<uint64_t>::max();
    for (size_t k = 0; k < lanes_.size(); ++k) {
      const size_t i = (next_ + k) % lanes_.size();
      Lane& l = lanes_[i];
      if (!closed_ && !eligible(l)) continue;
      const uint64_t need = bytes_of(*l.places.front());
      if (l.credit < need) {
        lack = std::min(lack, need - l.credit);
        continue;
      }
      l.credit -= need;
      FramePtr f = std::move(l.places.front());
      l.places.erase(l.places.begin());
      l.bytes -= need;
      bytes_ -= need;
      --frames_;
      f->large_in_decoder = need > kSmallFrameBytes;
      if (f->large_in_decoder) ++large_in_decoders_;
      next_ = i + 1;
      erase_empty_lanes();
      const bool now_empty = frames_ == 0;
      lock.unlock();
      room_.notify_all();
      if (now_empty) empty_.notify_all();
      return f;
    }
    for (Lane& l : lanes_) l.credit += lack;
  }
}

void DecodeQueue::close() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    closed_ = true;
  }
  ready_.notify_all();
  empty_.notify_all();
  room_.notify_all();
}

size_t DecodeQueue::frames() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return frames_;
}

uint64_t DecodeQueue::bytes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return bytes_;
}

}  // namespace fq::daemon
