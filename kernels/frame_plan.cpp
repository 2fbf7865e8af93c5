#include "kernels/frame_plan.h"

#include <algorithm>

#include "common/pair_table.h"
#include "kernels/cluster_control.h"

namespace fq {

namespace {

constexpr std::pair<PassKind, const char*> kPassNames[] = {
    {PassKind::kGrid, "grid"},
    {PassKind::kBaseQuadrics, "base_quadrics"},
    {PassKind::kNeighbourhoodQuadrics, "neighbourhood_quadrics"},
    {PassKind::kDiffusion, "diffusion"},
    {PassKind::kNoise, "noise"},
    {PassKind::kRefine, "refine"},
    {PassKind::kUpdate, "update"},
    {PassKind::kBilateralFilter, "bilateral_filter"},
    {PassKind::kScore, "score"},
    {PassKind::kLink, "link"},
    {PassKind::kModes, "modes"},
    {PassKind::kExportLinks, "export_links"},
};

// The passes of one run: quadrics when the filter or the clustering reads them, then the
// filter, then the clustering.
std::vector<PassKind> passes_of(const Params& p) {
  const FilterParams& f = p.filtering;
  std::vector<PassKind> out{PassKind::kGrid, PassKind::kBaseQuadrics};
  if (p.cluster || f.uses_quadrics()) {
    out.push_back(PassKind::kNeighbourhoodQuadrics);
    out.push_back(PassKind::kDiffusion);
  }
  if (p.filter) {
    if (f.method == FilterMethod::kQuadricRefined) {
      out.push_back(PassKind::kNoise);
      out.push_back(PassKind::kRefine);
    } else {
      out.push_back(f.uses_quadrics() ? PassKind::kUpdate : PassKind::kBilateralFilter);
    }
  }
  if (p.cluster) {
    for (PassKind k : {PassKind::kScore, PassKind::kLink, PassKind::kModes}) out.push_back(k);
    if (p.clustering.keep_links) out.push_back(PassKind::kExportLinks);
  }
  return out;
}

RunPlan plan_run(RunRole role, const Params& p) {
  const FilterParams& f = p.filtering;
  RunPlan r;
  r.role = role;
  r.params = p;
  r.passes = passes_of(p);
  r.grid_cell = f.sigma_s;
  r.sigma_b = extent_of(f.effective_sigma_b());
  r.sigma_s = extent_of(f.sigma_s);
  r.sigma_n = extent_of(f.effective_sigma_n());
  r.mollify = extent_of(0.5f * f.sigma_s);
  r.sigma_d = extent_of(p.clustering.sigma_d);
  r.sigma_r = f.sigma_r;
  r.sigma_q = p.clustering.sigma_q;
  return r;
}

/// The filter that makes the clustering geometry: normal-constrained, because the
/// unconstrained minimizer slides vertices onto creases, where both sides explain them.
Params geometry_filter(const Params& plain) {
  Params g = plain;
  g.filter = true;
  g.cluster = false;
  g.filtering.constrained = true;
  // The labels' geometry leaves the stream's history to the output's filter (one update a frame).
  g.filtering.temporal = 0.f;
  return g;
}

/// On the denoised mesh the quadrics can be sharper: half the filter's spatial and range
/// extents (measured on noisy fandisk, docs/QUALITY.md).
Params clustering_pass(const Params& plain) {
  Params c = plain;
  c.filter = false;
  c.cluster = true;
  c.filtering.sigma_s *= 0.5f;
  c.filtering.sigma_r *= 0.5f;
  c.filtering.sigma_b *= 0.5f;  // 0 (the default) stays the default, sigma_s / 2
  c.filtering.sigma_n *= 0.5f;
  return c;
}

/// Whether the frame's own filter moves the vertices as the geometry filter would: they differ
/// only in `constrained` (and the temporal step, which follows the runs), which only "qf" reads.
bool frame_filter_is_geometry(const Params& plain) {
  return plain.filtering.constrained || !plain.filtering.uses_quadrics();
}

}  // namespace

const char* pass_name(PassKind kind) { return second_of(kPassNames, kind).value_or("?"); }

bool visits_neighbourhood(PassKind kind) {
  return kind == PassKind::kNeighbourhoodQuadrics || kind == PassKind::kDiffusion ||
         kind == PassKind::kUpdate || kind == PassKind::kBilateralFilter || kind == PassKind::kScore ||
         kind == PassKind::kLink;
}

bool RunPlan::runs(PassKind kind) const {
  return std::find(passes.begin(), passes.end(), kind) != passes.end();
}

Extent RunPlan::extent(PassKind kind) const {
  switch (kind) {
    case PassKind::kNeighbourhoodQuadrics:
      return sigma_b;
    case PassKind::kDiffusion:
    case PassKind::kBilateralFilter:
      return sigma_s;
    case PassKind::kUpdate:
      return params.filtering.constrained ? sigma_n : Extent{};
    case PassKind::kScore:
    case PassKind::kLink:
      return sigma_d;
    default:
      return {};
  }
}

const char* RunPlan::timing_prefix() const {
  switch (role) {
    case RunRole::kGeometry:
      return "geometry.";
    case RunRole::kClustering:
      return "cluster.";
    default:
      return "";
  }
}

FramePlan plan_frame(const Params& params) {
  FramePlan plan;
  plan.params = params;
  plan.cluster_control = needs_cluster_control(params);
  if (!plan.cluster_control) {
    plan.runs.push_back(plan_run(RunRole::kFrame, params));
    return plan;
  }
  // The runs give the plain labels; cluster control's step makes them the asked-for ones.
  Params plain = params;
  plain.clustering.target_clusters = 0;
  plain.clustering.min_cluster_size = 0;
  plain.clustering.geometry = ClusterGeometry::kInput;
  if (params.clustering.target_clusters > 0) {
    plain.clustering.theta = 1.0f;  // cut nothing: the forest gives every other theta
    plain.clustering.keep_links = true;
  }
  if (params.clustering.effective_geometry() != ClusterGeometry::kFiltered) {
    plan.runs.push_back(plan_run(RunRole::kFrame, plain));
    return plan;
  }
  // The filtered geometry: the user's filter (when filtering) for the output, the geometry
  // filter (the same run when they agree), then the clustering pass on its result.
  if (plain.filter) {
    Params user = plain;
    user.cluster = false;
    plan.runs.push_back(plan_run(RunRole::kFrame, user));
  }
  if (!plain.filter || !frame_filter_is_geometry(plain))
    plan.runs.push_back(plan_run(RunRole::kGeometry, geometry_filter(plain)));
  plan.runs.push_back(plan_run(RunRole::kClustering, clustering_pass(plain)));
  return plan;
}

}  // namespace fq
