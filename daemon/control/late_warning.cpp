#include "daemon/control/late_warning.h"

#include <fmt/format.h>

#include "daemon/stream/stream_admission.h"

namespace fq::daemon {
namespace {

double p50(const std::map<std::string, Percentiles>& stages, const std::string& stage) {
  auto it = stages.find(stage);
  return it == stages.end() ? 0.0 : it->second.p50_ms;
}

double p(const StreamSnapshot& s, const char* stage, double Percentiles::*which) {
  auto it = s.stages.find(stage);
  return it == s.stages.end() ? 0.0 : it->second.*which;
}

}  // namespace

double clustering_p50_ms(const std::map<std::string, Percentiles>& stages) {
  double ms = 0;
  for (const auto& [name, percentiles] : stages) {
    const bool own = name == "engine.score" || name == "engine.link" || name == "engine.modes" ||
                     name == "engine.export_links";
    const bool added = name.starts_with("engine.geometry.") || name.starts_with("engine.cluster.") ||
                       name == "engine.cluster_control";
    if (own || added) ms += percentiles.p50_ms;
  }
  return ms;
}

std::string late_hint(const std::map<std::string, Percentiles>& stages, double budget_ms) {
  const double engine = p50(stages, "engine");
  const double wait = p50(stages, "wait");
  const double clustering = clustering_p50_ms(stages);
  // Medians of different frames do not add up exactly; "most" is judged on them all the same.
  const bool clustering_most = engine > 0 && 2 * clustering > engine;
  if (clustering_most && (engine > budget_ms || wait > engine)) {
    const bool alone = engine > budget_ms;
    return fmt::format(
        "{}, and clustering is {:.0f} of the engine's {:.0f} ms a frame: compute = \"filter\" on the "
        "stream turns clustering off (fqctl set <stream> compute=filter), else {}",
        alone ? "the engine alone takes longer than the budget" : "frames wait for an engine", clustering,
        engine, alone ? "raise budget_ms" : "lower the rate or add engines");
  }
  if (engine > budget_ms)
    return "the engine alone takes longer than the budget: raise budget_ms, lower the sigmas or use a GPU "
           "engine";
  if (wait > engine)
    return "frames wait for an engine: more frames than the engines serve (lower the rate, or add engines)";
  return "decode, encode or publishing take the rest of the budget";
}

std::optional<std::string> late_warning(const StreamSnapshot& now, const StreamCounters& before,
                                        double seconds, double budget_ms) {
  const uint64_t out = now.counters.frames_out - before.frames_out;
  const uint64_t late = now.counters.late - before.late;
  if (out < kLateWarningMinResults || 2 * late <= out) return std::nullopt;
  return fmt::format(
      "stream {}: {} of {} results late in the last {:.0f} s (budget {} ms, receive->publish p99 "
      "{:.0f} ms, engine p50 {:.0f} ms, wait p50 {:.0f} ms): {}",
      printable_id(now.stream_id), late, out, seconds, budget_ms,
      p(now, "receive_to_publish", &Percentiles::p99_ms), p(now, "engine", &Percentiles::p50_ms),
      p(now, "wait", &Percentiles::p50_ms), late_hint(now.stages, budget_ms));
}

}  // namespace fq::daemon
