#include "daemon/pipeline/work_budget.h"

#include <cmath>
#include <cstdio>
#include <string>

#include "kernels/frame_plan.h"
#include "kernels/refine_math.h"

namespace fq::daemon {

double expected_neighbours(double sigma) {
  constexpr double kVerticesPerUnitArea = 2.0 / 1.7320508075688772;  // equilateral sampling
  const double r = kRadiusPerSigma * sigma;
  return kVerticesPerUnitArea * M_PI * r * r;
}

// A regular mesh has two triangles per vertex and six triangles round a vertex: a face-normal
// pass visits the 13 faces that share a corner with each face (26 per vertex), a vertex pass
// and the per-round fan setup the 6 faces round each vertex.
double expected_refine_visits(float noise) {
  constexpr double kFaceNormalVisits = 2 * 13, kFanVisits = 6;
  const RefinePlan r = plan_refinement(RefineParams{noise, 1.f}, 0.f);
  const double round = kFaceNormalVisits * r.normal_passes.count + kFanVisits * (r.vertex_passes.count + 1);
  return round * r.rounds.count + kFanVisits * (kEnergyPasses + 2);
}

namespace {

/// One pass's share of the work: the parameter to lower for it, its value, visits per vertex.
struct Work {
  const char* name;
  double value;
  double per_vertex;
};

const char* sigma_name(PassKind kind) {
  switch (kind) {
    case PassKind::kNeighbourhoodQuadrics:
      return "sigma_b";
    case PassKind::kUpdate:
      return "sigma_n";
    case PassKind::kScore:
    case PassKind::kLink:
      return "sigma_d";
    default:
      return "sigma_s";
  }
}

template <class F>
void for_each_work(const Params& p, F&& f) {
  for (const RunPlan& run : plan_frame(p).runs) {
    for (PassKind kind : run.passes) {
      const Extent e = run.extent(kind);
      if (visits_neighbourhood(kind) && e.radius > 0.f)
        f(Work{sigma_name(kind), e.sigma, expected_neighbours(e.sigma)});
      if (kind == PassKind::kRefine) {
        const RefineParams& r = run.params.filtering.refine;
        const float noise = r.strength * (run.refinement_known() ? r.known_noise : kBudgetNoise);
        const bool known = run.refinement_known();
        f(Work{known ? "known_noise" : "strength", known ? r.known_noise : r.strength,
               expected_refine_visits(noise)});
      }
    }
  }
}

}  // namespace

double expected_neighbour_work(const Params& p, uint32_t vertices) {
  double per_vertex = 0;
  for_each_work(p, [&](const Work& w) { per_vertex += w.per_vertex; });
  return per_vertex * vertices;
}

Status check_work_budget(const Params& p, uint32_t vertices, double limit) {
  const double work = expected_neighbour_work(p, vertices);
  if (work <= limit) return {};
  Work top{"", 0, 0};
  for_each_work(p, [&](const Work& w) {
    if (w.per_vertex > top.per_vertex) top = w;
  });
  char msg[320];
  std::snprintf(
      msg, sizeof msg,
      "parameters ask for about %.3g neighbour visits on this frame (%s = %g: ~%.3g visits per vertex in "
      "its pass x %u vertices), over caps.max_neighbour_work = %.3g; lower %s or raise the cap",
      work, top.name, top.value, top.per_vertex, vertices, limit, top.name);
  return invalid_argument(msg);
}

}  // namespace fq::daemon
