#include "clients/fqfilter/file_report.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <numbers>
#include <ostream>
#include <string_view>

#include "clients/fqfilter/cli_options.h"
#include "common/sample_stats.h"
#include "core/param_table.h"
#include "kernels/refine_plan.h"

namespace fq::cli {

namespace {

/// A float parameter as the double with the same shortest decimal form (0.9f -> 0.9,
/// not 0.8999999761581421), so JSON shows the value the user typed.
double as_typed(float v) {
  char buf[32];
  const auto end = std::to_chars(buf, buf + sizeof buf, v).ptr;
  return std::strtod(std::string(buf, end).c_str(), nullptr);
}

// What "qf+" made of the noise: the estimate, the noise filtered for and the passes that gave.
nlohmann::json noise_json(const FileReport& r) {
  if (!r.noise_estimate || !r.filter_noise) return nullptr;
  const RefinePlan plan = plan_refinement(RefineParams{*r.filter_noise, 1.f}, 0.f);
  auto passes = [](Passes p) { return p.count > 0 ? p.count - 1 + p.last : 0.f; };
  return {
      {"estimated", *r.noise_estimate},
      {"residual", r.noise_residual ? nlohmann::json(*r.noise_residual) : nlohmann::json(nullptr)},
      {"directional", r.noise_directional ? nlohmann::json(*r.noise_directional) : nlohmann::json(nullptr)},
      {"direction", r.noise_direction},
      {"alignment", r.noise_alignment},
      {"filtered_for", *r.filter_noise},
      {"looks_clean", *r.noise_estimate < kLooksCleanBelow},
      {"rounds", passes(plan.rounds)},
      {"normal_passes", passes(plan.normal_passes)},
      {"vertex_passes", passes(plan.vertex_passes)}};
}

/// The noise fqfilter added (--noise, --noise-kind, --seed); "direction" is the kind's old
/// name, kept for the readers of iso and normal; "length" only where the kind has one.
nlohmann::json noise_added_json(const FileReport& r) {
  nlohmann::json j = {
      {"sigma", r.noise_sigma}, {"direction", noise_kind_name(r.noise_kind)}, {"seed", r.seed}};
  if (r.noise_kind == NoiseKind::kCorrelated || r.noise_kind == NoiseKind::kRipple)
    j["length"] = r.noise_length;
  return j;
}

nlohmann::json param_json(const ParamRow& row, const Params& p) {
  const double v = row.effective ? row.effective(p) : row.get(p);
  switch (row.kind) {
    case ParamKind::kBool:
      return v != 0.0;
    case ParamKind::kUint:
      return static_cast<uint32_t>(v);
    case ParamKind::kEnum:
      return format_param(row, v);
    case ParamKind::kFloat:
      break;
  }
  return as_typed(static_cast<float>(v));
}

// Every report row of the parameter table by its name, derived values resolved (sigma_b's
// 0 as sigma_s / 2); "qf+"'s noise rows under "refine", null for the other filters.
nlohmann::json params_json(const Params& p) {
  const bool refined = p.filtering.method == FilterMethod::kQuadricRefined;
  nlohmann::json out, refine;
  for (const ParamRow& row : param_table()) {
    if (!row.on(kReport)) continue;
    (row.group == ParamGroup::kNoise ? refine : out)[row.name] = param_json(row, p);
  }
  out["refine"] = refined ? refine : nullptr;
  return out;
}

nlohmann::json error_json(const std::optional<MeshError>& e) {
  if (!e) return nullptr;
  return {{"rmse_over_diagonal", e->rmse_over_diagonal},
          {"surface_rms_over_diagonal", e->surface.rms_over_diagonal},
          {"surface_max_over_diagonal", e->surface.max_over_diagonal},
          {"mfne_rad", e->mfne.mean_radians},
          {"mfne_deg", e->mfne.mean_radians * 180.0 / std::numbers::pi},
          {"faces_skipped", e->mfne.faces_skipped}};
}

nlohmann::json optional_json(const std::optional<double>& x) {
  return x ? nlohmann::json(*x) : nlohmann::json(nullptr);
}

// --sequence: the stream's prior and the flicker measures (null where not measured; NaN, a clean
// frame without area, is written as null by dump()).
nlohmann::json temporal_json(const FileReport& r) {
  nlohmann::json t = {{"prior_coverage", *r.prior_coverage},
                      {"prior_share", *r.prior_share},
                      {"history_reset", r.history_reset},
                      {"track", r.temporal_track},
                      {"ids_refused", r.ids_refused},
                      {"ids_wide", r.ids_wide ? nlohmann::json(*r.ids_wide) : nlohmann::json(nullptr)},
                      {"flicker", optional_json(r.flicker)},
                      {"flicker_normal", nullptr},
                      {"flicker_tangential", nullptr},
                      {"surface_flicker", nullptr},
                      {"shading_flicker", nullptr},
                      {"height_rms", nullptr},
                      {"smooth_normal_error_rad", nullptr}};
  if (r.flicker_parts) {
    t["flicker_normal"] = r.flicker_parts->normal;
    t["flicker_tangential"] = r.flicker_parts->tangential;
  }
  if (r.surface) {
    t["surface_flicker"] = optional_json(r.surface->surface_flicker);
    t["shading_flicker"] = optional_json(r.surface->shading_flicker);
    t["height_rms"] = r.surface->height_rms;
    t["smooth_normal_error_rad"] = r.surface->smooth_normal_error;
  }
  return t;
}

nlohmann::json recall_json(const std::optional<SharpEdgeRecall>& r) {
  if (!r) return nullptr;
  return {{"recall", r->recall},
          {"sharp_edges", r->sharp_edges},
          {"separated_edges", r->separated_edges},
          {"sharp_length", r->sharp_length},
          {"min_angle_deg", kSharpEdgeDegrees}};
}

void print_error_row(std::ostream& os, const char* what, const std::optional<MeshError>& e) {
  if (!e) return;
  os << "  " << std::left << std::setw(14) << what << std::right << std::scientific << std::setprecision(3)
     << std::setw(12) << e->rmse_over_diagonal << std::setw(12) << e->surface.rms_over_diagonal
     << std::setw(12) << e->surface.max_over_diagonal << std::fixed << std::setprecision(3) << std::setw(12)
     << e->mfne.mean_radians * 180.0 / std::numbers::pi << "\n";
}

}  // namespace

void summarize_timings(const std::vector<std::vector<PassTiming>>& runs, FileReport& report) {
  report.passes.clear();
  std::vector<double> totals;
  for (const auto& run : runs) {
    double t = 0.0;
    for (const PassTiming& p : run) t += p.ms;
    totals.push_back(t);
  }
  report.total_ms = median(totals);
  if (runs.empty()) return;
  for (const PassTiming& first : runs.front()) {
    std::vector<double> ms;
    for (const auto& run : runs) {
      for (const PassTiming& p : run) {
        if (p.name == first.name) ms.push_back(p.ms);
      }
    }
    report.passes.push_back({first.name, median(ms)});
  }
}

nlohmann::json to_json(const FileReport& r) {
  nlohmann::json j = {{"file", r.file}};
  if (!r.error.empty()) {
    j["error"] = r.error;
    return j;
  }
  nlohmann::json passes = nlohmann::json::array();
  for (const PassTiming& p : r.passes) passes.push_back({{"name", p.name}, {"ms", p.ms}});
  j.update(
      {{"output", r.output.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.output)},
       {"engine", r.engine},
       {"cuda_refused", r.cuda_refused.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.cuda_refused)},
       {"threads", r.threads},
       {"vertices", r.vertices},
       {"triangles", r.triangles},
       {"mean_edge", r.mean_edge},
       {"noise_estimate", noise_json(r)},
       {"moved", r.moved
                     ? nlohmann::json{{"mean", r.moved->mean}, {"p99", r.moved->p99}, {"max", r.moved->max}}
                     : nlohmann::json(nullptr)},
       {"welded_vertices", r.welded_vertices},
       {"params", params_json(r.params)},
       {"noise", r.noise_sigma > 0 ? noise_added_json(r) : nlohmann::json(nullptr)},
       {"repeat", r.repeat},
       {"timings_ms", {{"passes", passes}, {"total", r.total_ms}}},
       {"clusters", r.clusters ? nlohmann::json(*r.clusters) : nlohmann::json(nullptr)},
       {"theta_used", r.theta_used ? nlohmann::json(as_typed(*r.theta_used)) : nlohmann::json(nullptr)},
       {"warnings", r.warnings}});
  if (r.prior_coverage) j["temporal"] = temporal_json(r);
  if (r.reference.empty()) {
    j["metrics"] = nullptr;
  } else {
    j["metrics"] = {{"reference", r.reference},
                    {"input", error_json(r.input_error)},
                    {"output", error_json(r.output_error)},
                    {"sharp_edge_recall", recall_json(r.sharp_edges)}};
  }
  return j;
}

void print_human(const FileReport& r, std::ostream& os) {
  const auto flags = os.flags();
  os << r.file << ": " << r.vertices << " V, " << r.triangles << " T, mean edge " << std::setprecision(5)
     << r.mean_edge << ", engine " << r.engine;
  if (r.threads > 0) os << " (" << r.threads << " threads)";
  os << "\n";
  if (!r.cuda_refused.empty()) os << "  CUDA not used: " << r.cuda_refused << "\n";
  os << "  " << std::left << std::setw(24) << "pass" << std::right << std::setw(10) << "ms"
     << "\n"
     << std::fixed;
  for (const PassTiming& p : r.passes)
    os << "  " << std::left << std::setw(24) << p.name << std::right << std::setw(10) << std::setprecision(2)
       << p.ms << "\n";
  os << "  " << std::left << std::setw(24) << "total" << std::right << std::setw(10) << std::setprecision(2)
     << r.total_ms;
  if (r.repeat > 1) os << "  (median of " << r.repeat << " runs)";
  os << "\n";
  if (r.noise_estimate && r.filter_noise) {
    os << std::setprecision(3) << "  noise: " << *r.noise_estimate << " mean edges estimated";
    if (*r.filter_noise != *r.noise_estimate) os << ", filtered for " << *r.filter_noise;
    if (r.noise_residual && *r.noise_residual > 0.f)
      os << " (of a residual " << *r.noise_residual << ": the rest read as the surface's detail)";
    os << "\n";
    const bool estimated = r.params.filtering.refine.known_noise == 0.f;
    if (r.noise_directional && *r.noise_directional > 0.f) {
      const float along_normals = *r.noise_directional * r.noise_alignment;
      os << "  directional noise: " << *r.noise_directional << " mean edges along (" << r.noise_direction[0]
         << ", " << r.noise_direction[1] << ", " << r.noise_direction[2]
         << "), one direction for the whole mesh (a range sensor's line of sight): " << along_normals
         << " of it along the normals";
      // As refine_plan.h plans it: a noise given is white noise, with no directional part.
      if (estimated)
        os << (along_normals > *r.noise_estimate ? ", filtered for" : "")
           << "; its slides within the surface undone\n";
      else
        os << "; not used: --known-noise filters for white noise of that size\n";
    }
    const float read = *r.filter_noise / std::fmax(r.params.filtering.refine.strength, 1e-6f);
    if (estimated && *r.noise_estimate < kLooksCleanBelow && read < kLooksCleanBelow)
      os << "  input looks clean: filtered lightly (--known-noise 0.1 filters it as 0.1 mean edges of "
            "noise)\n";
    else if (estimated && read < kReadsLightBelow && r.params.filtering.refine.strength <= 1.f)
      os << "  read as light noise: filtered lightly; for noise this estimate does not see (a raw scan's "
            "correlated noise) --strength 3 filters as for three times the noise\n";
  }
  if (r.welded_vertices > 0)
    os << "  seams: " << r.welded_vertices << " coincident vertices filtered as one with their twins\n";
  if (r.moved)
    os << std::setprecision(3) << "  moved: mean " << r.moved->mean << ", p99 " << r.moved->p99 << ", max "
       << r.moved->max << " mean edges\n";
  if (r.prior_coverage) {
    if (std::string_view(r.temporal_track) == "ids")
      os << std::setprecision(3) << "  temporal (ids): input averaged with the last, weight "
         << *r.prior_share << ", wide motion share " << r.ids_wide.value_or(0.f);
    else
      os << std::setprecision(3) << "  temporal: " << *r.prior_coverage
         << " of vertices near the last result, pull " << *r.prior_share;
    if (r.ids_refused) os << " (ids refused: they do not follow a smooth motion)";
    if (r.history_reset) os << " (scene cut: history reset)";
    if (r.flicker) os << ", flicker " << *r.flicker << " mean edges";
    if (r.flicker_parts)
      os << " (" << r.flicker_parts->normal << " across the surface, " << r.flicker_parts->tangential
         << " along it)";
    os << "\n";
    if (r.surface) {
      os << "  surface: height RMS " << r.surface->height_rms << " mean edges, smooth-normal error "
         << r.surface->smooth_normal_error << " rad";
      if (r.surface->surface_flicker)
        os << ", SF " << *r.surface->surface_flicker << " mean edges, ShF " << *r.surface->shading_flicker;
      os << "\n";
    }
  }
  if (r.clusters) {
    os << "  clusters: " << *r.clusters;
    if (r.theta_used && r.params.clustering.target_clusters > 0)
      os << " (theta " << std::setprecision(4) << *r.theta_used << ")";
    os << "\n";
  }
  if (r.sharp_edges)
    os << "  sharp-edge recall: " << std::setprecision(3) << r.sharp_edges->recall << " of "
       << r.sharp_edges->sharp_edges << " edges over " << std::setprecision(0) << kSharpEdgeDegrees
       << " deg\n";
  if (!r.reference.empty()) {
    os << "  error vs " << r.reference << "\n  " << std::left << std::setw(14) << "" << std::right
       << std::setw(12) << "RMSE/diag" << std::setw(12) << "surf RMS" << std::setw(12) << "surf max"
       << std::setw(12) << "MFNE (deg)"
       << "\n";
    print_error_row(os, r.noise_sigma > 0 ? "noisy input" : "input", r.input_error);
    print_error_row(os, "result", r.output_error);
  }
  if (!r.output.empty()) os << "  wrote " << r.output << "\n";
  os.flags(flags);
}

}  // namespace fq::cli
