#include "daemon/pipeline/latency_policy.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace fq::daemon {

namespace {

int64_t steady_ns() { return CancelToken::Clock::now().time_since_epoch().count(); }

constexpr double kWindowNs = FrameSlots::kShareWindowS * 1e9;

}  // namespace

double FrameSlots::usage_at(SlotState& s, int64_t now_ns) {
  if (now_ns > s.usage_ns) {
    s.usage_s *= std::exp(-double(now_ns - s.usage_ns) / kWindowNs);
    s.usage_ns = now_ns;
  }
  return s.usage_s;
}

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
    const int64_t now = steady_ns();
    offered_[stream.id()] = now;
    review_runs(now);
  }
  ready_.notify_one();
  return loser;
}

bool FrameSlots::take(FramePtr& out, std::vector<FramePtr>& stale, std::chrono::milliseconds wait,
                      YieldRequest* yield) {
  std::unique_lock<std::mutex> lock(mutex_);
  const auto ready = [&] { return closed_ || !waiting_.empty(); };
  ++idle_takers_;
  if (wait == std::chrono::milliseconds::max()) {
    ready_.wait(lock, ready);
  } else if (!ready_.wait_for(lock, wait, ready)) {
    --idle_takers_;
    return true;  // nothing came: the caller does its idle work
  }
  --idle_takers_;
  if (waiting_.empty()) return false;
  const int64_t now = steady_ns();
  while (!waiting_.empty()) {
    // Least recent engine time first; among equals the stream served least recently (round
    // robin), then the oldest frame. Oldest-frame-first alone starves a stream under overload:
    // when its waiting frame is superseded while the engine is busy, the replacement is always
    // younger than the other stream's, which then wins every time. Round robin by frames alone
    // let a stream whose frames take seconds hold the engine against one whose frames take
    // milliseconds.
    auto best = waiting_.begin();
    double best_usage = usage_at((*best)->slot, now);
    for (auto it = std::next(waiting_.begin()); it != waiting_.end(); ++it) {
      SlotState& s = (*it)->slot;
      const SlotState& b = (*best)->slot;
      const double u = usage_at(s, now);
      if (u < best_usage ||
          (u == best_usage &&
           (s.served < b.served || (s.served == b.served && s.waiting->receive_ns < b.waiting->receive_ns)))) {
        best = it;
        best_usage = u;
      }
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
    if (yield != nullptr) {
      yield->requested.store(false);
      runs_.push_back({f->stream, yield, now, best_usage});
    }
    out = std::move(f);
    review_runs(now);
    return true;
  }
  return true;  // only stale frames this time
}

void FrameSlots::finish(YieldRequest* yield, double seconds) {
  StreamPtr stream;  // released after the lock: the slots never end a stream under their lock
  std::lock_guard<std::mutex> lock(mutex_);
  const auto run = std::find_if(runs_.begin(), runs_.end(), [&](const Run& r) { return r.yield == yield; });
  if (run == runs_.end()) return;
  stream = std::move(run->stream);
  SlotState& s = stream->slot;
  usage_at(s, steady_ns());
  s.usage_s += seconds;
  s.cost_s = s.cost_s > 0 ? 0.7 * s.cost_s + 0.3 * seconds : seconds;
  runs_.erase(run);
}

void FrameSlots::charge(Stream& stream, double seconds) {
  std::lock_guard<std::mutex> lock(mutex_);
  usage_at(stream.slot, steady_ns());
  stream.slot.usage_s += seconds;
}

void FrameSlots::set_engines(int engines) {
  std::lock_guard<std::mutex> lock(mutex_);
  engines_ = std::max(1, engines);
}

void FrameSlots::review_runs(int64_t now_ns) {
  for (auto it = offered_.begin(); it != offered_.end();)
    it = double(now_ns - it->second) < kWindowNs ? std::next(it) : offered_.erase(it);
  if (runs_.empty()) return;
  // How many streams are active: offered a frame within the window, waiting or running.
  int active = static_cast<int>(offered_.size());
  const auto recent = [&](const Stream& s) { return offered_.count(s.id()) != 0; };
  for (const Stream* s : waiting_)
    if (!recent(*s)) ++active;
  for (size_t i = 0; i < runs_.size(); ++i) {
    const Stream& s = *runs_[i].stream;
    const bool counted = recent(s) || s.slot.waiting ||
                         std::any_of(runs_.begin(), runs_.begin() + i, [&](const Run& r) { return r.stream.get() == &s; });
    if (!counted) ++active;
  }
  // The waiting stream of least usage.
  Stream* waiting = nullptr;
  double waiting_usage = 0;
  for (Stream* s : waiting_) {
    const double u = usage_at(s->slot, now_ns);
    if (!waiting || u < waiting_usage) {
      waiting = s;
      waiting_usage = u;
    }
  }
  const double waiting_cost = waiting ? waiting->slot.cost_s : 0;
  const double share = kShareWindowS * engines_ / std::max(1, active);
  // The run to stop, if any: the one whose stream had used most when it started.
  Run* to_stop = nullptr;
  if (idle_takers_ == 0 && waiting != nullptr && waiting_usage < 0.5 * share) {
    for (Run& r : runs_) {
      if (r.stream.get() == waiting) continue;
      if (!to_stop || r.usage_at_start_s > to_stop->usage_at_start_s) to_stop = &r;
    }
  }
  for (Run& r : runs_) {
    if (&r != to_stop) {
      r.yield->requested.store(false);
      continue;
    }
    // Due after a slice and four of the waiting stream's frames, once the stream's usage with
    // this run's time passes twice the waiting stream's and a slice.
    const double frames_s = waiting_cost > 0 ? 4.0 * waiting_cost : kColdSliceS;
    const double after_s = std::max({kSliceS, frames_s, 2.0 * waiting_usage + kSliceS - r.usage_at_start_s});
    r.yield->after_ns.store(r.start_ns + static_cast<int64_t>(after_s * 1e9));
    r.yield->requested.store(true);
  }
}

void FrameSlots::close() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    closed_ = true;
  }
  ready_.notify_all();
}

}  // namespace fq::daemon
