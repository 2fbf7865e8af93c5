#include "daemon/latency_policy.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fq::daemon {

namespace {

int64_t steady_ns() { return CancelToken::Clock::now().time_since_epoch().count(); }

constexpr double kWindowNs = FrameSlots::kShareWindowS * 1e9;

}  // namespace

double FrameSlots::usage_at(Stream& s, int64_t now_ns) {
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
    Stream& s = streams_[frame->stream_id];
    const bool behind_taken = s.taken_any && frame->arrival <= s.last_taken_arrival;
    if (behind_taken || (s.waiting && s.waiting->arrival > frame->arrival)) return frame;
    if (s.waiting)
      loser = std::move(s.waiting);
    else
      ++waiting_;
    s.waiting = std::move(frame);
    s.offered_ns = steady_ns();
    review_runs(s.offered_ns);
  }
  ready_.notify_one();
  return loser;
}

bool FrameSlots::take(FramePtr& out, std::vector<FramePtr>& stale, std::chrono::milliseconds wait,
                      YieldRequest* yield) {
  std::unique_lock<std::mutex> lock(mutex_);
  const auto ready = [&] { return closed_ || waiting_ > 0; };
  ++idle_takers_;
  if (wait == std::chrono::milliseconds::max()) {
    ready_.wait(lock, ready);
  } else if (!ready_.wait_for(lock, wait, ready)) {
    --idle_takers_;
    return true;  // nothing came: the caller does its idle work
  }
  --idle_takers_;
  if (waiting_ == 0) return false;
  const int64_t now = steady_ns();
  while (waiting_ > 0) {
    // Least recent engine time first; among equals the stream served least recently (round
    // robin), then the oldest frame. Oldest-frame-first alone starves a stream under overload:
    // when its waiting frame is superseded while the engine is busy, the replacement is always
    // younger than the other stream's, which then wins every time. Round robin by frames alone
    // let a stream whose frames take seconds hold the engine against one whose frames take
    // milliseconds.
    Stream* best = nullptr;
    const char* best_id = nullptr;
    double best_usage = 0;
    for (auto& [id, s] : streams_) {
      if (!s.waiting) continue;
      const double u = usage_at(s, now);
      if (!best || u < best_usage ||
          (u == best_usage && (s.served < best->served || (s.served == best->served &&
                                                           s.waiting->receive_ns < best->waiting->receive_ns)))) {
        best = &s;
        best_id = id.c_str();
        best_usage = u;
      }
    }
    best->served = ++served_;
    FramePtr f = std::move(best->waiting);
    --waiting_;
    best->last_taken_arrival = f->arrival;
    best->taken_any = true;
    if (is_stale(f->receive_ns, wall_ns(), f->settings.budget_ms)) {
      stale.push_back(std::move(f));
      continue;
    }
    f->ticket = best->next_ticket++;
    f->ticketed = true;
    if (yield != nullptr) {
      yield->requested.store(false);
      runs_.push_back({best_id, yield, now, best_usage});
    }
    out = std::move(f);
    review_runs(now);
    return true;
  }
  return true;  // only stale frames this time
}

void FrameSlots::finish(YieldRequest* yield, double seconds) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto run = std::find_if(runs_.begin(), runs_.end(), [&](const Run& r) { return r.yield == yield; });
  if (run == runs_.end()) return;
  const auto s = streams_.find(run->stream_id);
  if (s != streams_.end()) {
    usage_at(s->second, steady_ns());
    s->second.usage_s += seconds;
    double& cost = s->second.cost_s;
    cost = cost > 0 ? 0.7 * cost + 0.3 * seconds : seconds;
  }
  runs_.erase(run);
}

void FrameSlots::charge(const std::string& stream_id, double seconds) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto s = streams_.find(stream_id);
  if (s == streams_.end()) return;
  usage_at(s->second, steady_ns());
  s->second.usage_s += seconds;
}

void FrameSlots::set_engines(int engines) {
  std::lock_guard<std::mutex> lock(mutex_);
  engines_ = std::max(1, engines);
}

void FrameSlots::review_runs(int64_t now_ns) {
  if (runs_.empty()) return;
  // The waiting stream of least usage, and how many streams are active.
  const std::string* waiting_id = nullptr;
  double waiting_usage = 0, waiting_cost = 0;
  int active = 0;
  for (auto& [id, s] : streams_) {
    const bool running = std::any_of(runs_.begin(), runs_.end(), [&](const Run& r) { return r.stream_id == id; });
    if (running || s.waiting || (s.offered_ns != 0 && double(now_ns - s.offered_ns) < kWindowNs)) ++active;
    if (!s.waiting) continue;
    const double u = usage_at(s, now_ns);
    if (!waiting_id || u < waiting_usage) {
      waiting_id = &id;
      waiting_usage = u;
      waiting_cost = s.cost_s;
    }
  }
  const double share = kShareWindowS * engines_ / std::max(1, active);
  // The run to stop, if any: the one whose stream had used most when it started.
  Run* to_stop = nullptr;
  if (idle_takers_ == 0 && waiting_id != nullptr && waiting_usage < 0.5 * share) {
    for (Run& r : runs_) {
      if (r.stream_id == *waiting_id) continue;
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
