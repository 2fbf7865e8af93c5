#include "daemon/latency_policy.h"

namespace fq::daemon {

FramePtr FrameSlots::offer(FramePtr frame) {
  FramePtr loser;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    Stream& stream = *frame->stream;
    SlotState& s = stream.slot;
    const bool behind_taken = s.taken_any && frame->arrival <= s.last_taken_arrival;
    if (behind_taken || (s.waiting && s.waiting->arrival > frame->arrival)) return frame;
    if (s.waiting)
      loser = std::move(s.waiting);
    else
      waiting_.push_back(&stream);
    s.waiting = std::move(frame);
  }
  ready_.notify_one();
  return loser;
}

bool FrameSlots::take(FramePtr& out, std::vector<FramePtr>& stale, std::chrono::milliseconds wait) {
  std::unique_lock<std::mutex> lock(mutex_);
  const auto ready = [&] { return closed_ || !waiting_.empty(); };
  if (wait == std::chrono::milliseconds::max())
    ready_.wait(lock, ready);
  else if (!ready_.wait_for(lock, wait, ready))
    return true;  // nothing came: the caller does its idle work
  if (waiting_.empty()) return false;
  while (!waiting_.empty()) {
    // Round robin: the stream served least recently goes first (oldest frame among equals).
    // Oldest-frame-first alone starves a stream under overload: when its waiting frame is
    // superseded while the engine is busy, the replacement is always younger than the other
    // stream's, which then wins every time.
    auto best = waiting_.begin();
    for (auto it = waiting_.begin(); it != waiting_.end(); ++it) {
      const SlotState &s = (*it)->slot, &b = (*best)->slot;
      if (s.served < b.served || (s.served == b.served && s.waiting->receive_ns < b.waiting->receive_ns)) best = it;
    }
    SlotState& s = (*best)->slot;
    *best = waiting_.back();
    waiting_.pop_back();
    s.served = ++served_;
    FramePtr f = std::move(s.waiting);  // f holds the stream now
    s.last_taken_arrival = f->arrival;
    s.taken_any = true;
    if (is_stale(f->receive_ns, wall_ns(), f->settings.budget_ms)) {
      stale.push_back(std::move(f));
      continue;
    }
    f->ticket = s.next_ticket++;
    f->ticketed = true;
    out = std::move(f);
    return true;
  }
  return true;  // only stale frames this time
}

void FrameSlots::close() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    closed_ = true;
  }
  ready_.notify_all();
}

}  // namespace fq::daemon
