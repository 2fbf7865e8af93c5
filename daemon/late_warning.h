// A warning line when a stream has been mostly late over a [stats] interval, so that a
// budget the engines cannot meet shows in the log as a warning, not only as a count:
//   stream cam0: 9 of 9 results late in the last 60 s (budget 100 ms, receive->publish p99
//   12600 ms, engine p50 1400 ms): the engine alone takes longer than the budget
#pragma once

#include <optional>
#include <string>

#include "daemon/stream_registry.h"

namespace fq::daemon {

/// At least this many results in the interval before "mostly late" is judged (one late
/// warm-up frame is not a trend).
inline constexpr uint64_t kLateWarningMinResults = 3;

/// The warning when more than half of the stream's results since `before` were late;
/// nullopt otherwise.
std::optional<std::string> late_warning(const StreamSnapshot& now, const StreamCounters& before, double seconds,
                                        double budget_ms);

}  // namespace fq::daemon
