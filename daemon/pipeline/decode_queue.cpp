#include "daemon/pipeline/decode_queue.h"

#include <algorithm>

namespace fq::daemon {

uint64_t DecodeQueue::bytes_of(const FrameJob& f) {
  uint64_t n = 0;
  for (const zmq::message_t& c : f.chunks) n += c.size();
  return n;
}

bool DecodeQueue::room_for(uint64_t bytes) const {
  if (items_.empty()) return true;  // a frame over the byte bound goes alone
  return items_.size() < max_frames_ && bytes_ + bytes <= max_bytes_;
}

void DecodeQueue::set_bounds(size_t max_frames, uint64_t max_bytes) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    max_frames_ = std::max<size_t>(1, max_frames);
    max_bytes_ = max_bytes;
  }
  room_.notify_all();
}

bool DecodeQueue::push(FramePtr f, FramePtr& superseded) {
  const uint64_t bytes = bytes_of(*f);
  {
    std::unique_lock<std::mutex> lock(mutex_);
    auto older = std::find_if(items_.begin(), items_.end(), [&](const FramePtr& q) { return q->stream_id == f->stream_id; });
    if (older != items_.end()) {
      bytes_ -= bytes_of(**older);
      superseded = std::move(*older);
      items_.erase(older);
    }
    room_.wait(lock, [&] { return closed_ || room_for(bytes); });
    if (closed_) return false;
    bytes_ += bytes;
    items_.push_back(std::move(f));
  }
  ready_.notify_one();
  return true;
}

std::optional<FramePtr> DecodeQueue::pop() {
  std::unique_lock<std::mutex> lock(mutex_);
  ready_.wait(lock, [&] { return closed_ || !items_.empty(); });
  if (items_.empty()) return std::nullopt;
  FramePtr f = std::move(items_.front());
  items_.pop_front();
  bytes_ -= bytes_of(*f);
  lock.unlock();
  room_.notify_all();
  return f;
}

void DecodeQueue::close() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    closed_ = true;
  }
  ready_.notify_all();
  room_.notify_all();
}

size_t DecodeQueue::frames() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return items_.size();
}

uint64_t DecodeQueue::bytes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return bytes_;
}

}  // namespace fq::daemon
