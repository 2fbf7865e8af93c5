// What each way a stream loses frames or results means, and what to change, in words for the
// log: after a stream's [stats] line, one line per reason that counted in the interval:
//   [drops] stream=cam0 reason=superseded count=41: a newer frame of the stream arrived while
//   this one waited for a decoder or an engine (only the latest frame waits), so it got no
//   result -> the engines are slower than the stream's frame rate: lower the rate, make frames
//   cheaper (compute = "filter", smaller sigmas) or add engines
// The reasons are the per-stream counters of stream.h that stand for a frame without a result
// (superseded, stale, preempted, time_limited, memory) or a result a subscriber missed
// (subscriber_overflow).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "daemon/stream/stream.h"

namespace fq::daemon {

struct DropReason {
  const char* name;  ///< the word in the line (the counter's name without _total)
  uint64_t StreamCounters::*counter;
  const char* meaning;  ///< what happened to the frame or result
  const char* action;   ///< what to change
};

/// Every reason, in the order of the lines.
const std::vector<DropReason>& drop_reasons();

/// One `[drops]` line per reason whose counter grew from `before` to `now`, for `stream_id`.
std::vector<std::string> drop_lines(const std::string& stream_id, const StreamCounters& now,
                                    const StreamCounters& before);

}  // namespace fq::daemon
