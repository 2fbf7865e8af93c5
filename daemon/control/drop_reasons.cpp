#include "daemon/control/drop_reasons.h"

#include <fmt/format.h>

namespace fq::daemon {

const std::vector<DropReason>& drop_reasons() {
  static const std::vector<DropReason> reasons = {
      {"superseded", &StreamCounters::superseded,
       "a newer frame of the stream arrived while this one waited for a decoder or an engine (only the "
       "latest frame waits), or the decode queue was full and this frame's connection held the most "
       "bytes, so it got no result",
       "the engines are slower than the stream's frame rate: lower the rate, make frames cheaper "
       "(compute = \"filter\", smaller sigmas) or add engines"},
      {"stale", &StreamCounters::dropped_stale,
       "the frame was older than budget_ms when a decoder or an engine was free, so it was dropped "
       "without a result",
       "frames wait longer than the budget: raise budget_ms if later results are still of use, else "
       "lower the rate or add engines"},
      {"preempted", &StreamCounters::preempted,
       "the frame, which could not meet budget_ms, was stopped on the engine so that a lighter "
       "stream's frame could meet its own, the engines being oversubscribed (an error result)",
       "this stream's frames take longer than its budget on engines other streams need: raise "
       "budget_ms, make them cheaper (compute = \"filter\", smaller sigmas) or add an engine"},
      {"time_limited", &StreamCounters::time_limited,
       "the frame ran past caps.engine_time_limit_s and was stopped (an error result)",
       "the frame is too heavy for the limit: fewer vertices or smaller sigmas, or raise "
       "caps.engine_time_limit_s"},
      {"subscriber_overflow", &StreamCounters::subscriber_overflows,
       "a subscriber's queue was full (caps.max_subscriber_results), so it missed results (perhaps "
       "more than one per overflow)",
       "a subscriber reads slower than results come: make it read faster, subscribe only to the streams "
       "it needs, or raise caps.max_subscriber_results"},
      {"memory", &StreamCounters::dropped_memory,
       "the frame did not fit caps.memory_budget_mb once the idle streams' /latest copies and the other "
       "streams' temporal histories and id tracks were dropped, so it was dropped without a result",
       "fqd keeps more per stream than the budget: raise caps.memory_budget_mb (the host has room), lower "
       "caps.max_streams, send smaller frames, or turn temporal filtering or track_ids off where not needed"},
  };
  return reasons;
}

std::vector<std::string> drop_lines(const std::string& stream_id, const StreamCounters& now,
                                    const StreamCounters& before) {
  std::vector<std::string> out;
  for (const DropReason& r : drop_reasons()) {
    const uint64_t n = now.*r.counter - before.*r.counter;
    if (n > 0)
      out.push_back(fmt::format("[drops] stream={} reason={} count={}: {} -> {}", stream_id, r.name, n,
                                r.meaning, r.action));
  }
  return out;
}

}  // namespace fq::daemon
