// A warning line when a stream has been mostly late over a [stats] interval, so that a
// budget the engines cannot meet shows in the log as a warning, not only as a count:
//   stream cam0: 9 of 9 results late in the last 60 s (budget 100 ms, receive->publish p99
//   12600 ms, engine p50 1400 ms): the engine alone takes longer than the budget ...
// The hint names the costliest lever: with clustering most of the engine's time, the stream's
// compute = "filter" (late_hint).
#pragma once

#include <map>
#include <optional>
#include <string>

#include "daemon/stream/stream_registry.h"

namespace fq::daemon {

/// At least this many results in the interval before "mostly late" is judged (one late
/// warm-up frame is not a trend).
inline constexpr uint64_t kLateWarningMinResults = 3;

/// Engine time of a frame spent on clustering, from the stage medians of `stages`: the
/// frame's own clustering passes ("engine.score", "engine.link", "engine.modes",
/// "engine.export_links") and every pass of the runs that clustering adds ("engine.geometry.*",
/// "engine.cluster.*", "engine.cluster_control"). What compute = "filter" would save.
double clustering_p50_ms(const std::map<std::string, Percentiles>& stages);

/// The likeliest cause of late results from the stage medians and what to change: the engine
/// (clustering, when it is most of the engine's time: compute = "filter"), waiting for an
/// engine, or the rest of the pipeline.
std::string late_hint(const std::map<std::string, Percentiles>& stages, double budget_ms);

/// The warning when more than half of the stream's results since `before` were late;
/// nullopt otherwise.
std::optional<std::string> late_warning(const StreamSnapshot& now, const StreamCounters& before,
                                        double seconds, double budget_ms);

}  // namespace fq::daemon
