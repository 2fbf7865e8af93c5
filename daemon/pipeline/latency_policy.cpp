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
    // The stream's frame interval, from receipt times (a frame decoded late says nothing).
    if (s.last_receive_ns > 0 && frame->receive_ns > s.last_receive_ns) {
      const double dt = double(frame->receive_ns - s.last_receive_ns) * 1e-9;
      s.interval_s = s.interval_s > 0 ? 0.7 * s.interval_s + 0.3 * dt : dt;
    }
    s.last_receive_ns = std::max(s.last_receive_ns, frame->receive_ns);
    if (s.waiting)
      loser = std::move(s.waiting);
    else
      waiting_.push_back(&stream);
    s.waiting = std::move(frame);
    review_runs(steady_ns());
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
          (u == best_usage && (s.served < b.served ||
                               (s.served == b.served && s.waiting->receive_ns < b.waiting->receive_ns)))) {
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
      const auto budget_ns = static_cast<int64_t>(f->settings.budget_ms * 1e6);
      runs_.push_back({f->stream, yield, now, f->receive_ns + budget_ns + (now - wall_ns()), {}});
    }
    out = std::move(f);
    review_runs(now);
    return true;
  }
  return true;  // only stale frames this time
}

void FrameSlots::finish(YieldRequest* yield, double seconds, bool preempted) {
  // Released after the lock: the slots never end a stream under their lock.
  StreamPtr stream, for_stream;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto run = std::find_if(runs_.begin(), runs_.end(), [&](const Run& r) { return r.yield == yield; });
    if (run == runs_.end()) return;
    stream = std::move(run->stream);
    if (preempted) for_stream = run->for_stream.lock();
    SlotState& s = stream->slot;
    usage_at(s, steady_ns());
    s.usage_s += seconds;
    // A stopped run says only that the frame costs at least this much.
    if (preempted)
      s.cost_s = std::max(s.cost_s, seconds);
    else
      s.cost_s = s.cost_s > 0 ? 0.7 * s.cost_s + 0.3 * seconds : seconds;
    s.preempted = preempted;
    runs_.erase(run);
  }
  if (for_stream) for_stream->count(&StreamCounters::preempted_others);
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

double FrameSlots::demand(const SlotState& s) { return s.interval_s > 0 ? s.cost_s / s.interval_s : 0.0; }

int64_t FrameSlots::stop_time(const Run& r, const Stream& w, int64_t now_ns, int64_t wall_to_steady_ns) {
  const FrameJob& f = *w.slot.waiting;
  // The latest start at which the waiting frame still meets its budget.
  const int64_t w_latest = f.receive_ns + wall_to_steady_ns +
                           static_cast<int64_t>(f.settings.budget_ms * 1e6) -
                           static_cast<int64_t>(w.slot.cost_s * 1e9);
  // The running frame's expected end: its stream's cost, or later (now, at least).
  const int64_t r_end = r.start_ns + static_cast<int64_t>(r.stream->slot.cost_s * 1e9);
  // From when the waiting frame misses its budget unless the engine is given up, and from when
  // the running frame cannot meet its own.
  const int64_t other_lost = r_end > w_latest ? now_ns : w_latest;
  const int64_t own_lost = r_end > r.deadline_ns ? now_ns : r.deadline_ns;
  const int64_t at = std::max({other_lost, own_lost, r.start_ns + static_cast<int64_t>(kSliceS * 1e9)});
  // Stopping later than the waiting frame's latest start would not save it.
  return at <= w_latest ? at : -1;
}

void FrameSlots::review_runs(int64_t now_ns) {
  if (runs_.empty()) return;
  const int64_t wall_to_steady = now_ns - wall_ns();
  // What the streams running and waiting ask for (each stream once).
  double asked = 0;
  for (const Stream* w : waiting_) asked += demand(w->slot);
  for (size_t i = 0; i < runs_.size(); ++i) {
    const Stream* s = runs_[i].stream.get();
    const bool seen = s->slot.waiting != nullptr ||
                      std::any_of(runs_.begin(), runs_.begin() + static_cast<std::ptrdiff_t>(i),
                                  [&](const Run& r) { return r.stream.get() == s; });
    if (!seen) asked += demand(s->slot);
  }
  // The run to stop, if any, and when: the earliest stop that saves a waiting frame.
  Run* to_stop = nullptr;
  const Stream* stop_for = nullptr;
  int64_t stop_at = 0;
  if (idle_takers_ == 0 && asked > engines_) {
    for (Run& r : runs_) {
      if (r.stream->slot.preempted) continue;  // guaranteed progress
      for (const Stream* w : waiting_) {
        if (w == r.stream.get() || demand(r.stream->slot) <= demand(w->slot)) continue;
        const int64_t at = stop_time(r, *w, now_ns, wall_to_steady);
        if (at >= 0 && (!to_stop || at < stop_at)) {
          to_stop = &r;
          stop_for = w;
          stop_at = at;
        }
      }
    }
  }
  for (Run& r : runs_) {
    if (&r != to_stop) {
      r.yield->requested.store(false);
      continue;
    }
    r.for_stream = stop_for->slot.waiting->stream;  // the waiting frame holds its stream
    r.yield->after_ns.store(stop_at);
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
