#include "daemon/late_warning.h"

#include <fmt/format.h>

#include "daemon/stream_admission.h"

namespace fq::daemon {
namespace {

double p(const StreamSnapshot& s, const char* stage, double Percentiles::*which) {
  auto it = s.stages.find(stage);
  return it == s.stages.end() ? 0.0 : it->second.*which;
}

}  // namespace

std::optional<std::string> late_warning(const StreamSnapshot& now, const StreamCounters& before, double seconds,
                                        double budget_ms) {
  const uint64_t out = now.counters.frames_out - before.frames_out;
  const uint64_t late = now.counters.late - before.late;
  if (out < kLateWarningMinResults || 2 * late <= out) return std::nullopt;
  const double engine_p50 = p(now, "engine", &Percentiles::p50_ms);
  const double wait_p50 = p(now, "wait", &Percentiles::p50_ms);
  // The likeliest cause from the stage medians: the work itself, or waiting for an engine.
  const char* why = engine_p50 > budget_ms ? "the engine alone takes longer than the budget: raise budget_ms, "
                                             "lower the sigmas or use a GPU engine"
                    : wait_p50 > engine_p50 ? "frames wait for an engine: more frames than the engines serve "
                                              "(lower the rate, or add engines)"
                                            : "decode, encode or publishing take the rest of the budget";
  return fmt::format("stream {}: {} of {} results late in the last {:.0f} s (budget {} ms, receive->publish p99 "
                     "{:.0f} ms, engine p50 {:.0f} ms, wait p50 {:.0f} ms): {}",
                     printable_id(now.stream_id), late, out, seconds, budget_ms,
                     p(now, "receive_to_publish", &Percentiles::p99_ms), engine_p50, wait_p50, why);
}

}  // namespace fq::daemon
