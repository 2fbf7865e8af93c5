// What one frame runs, resolved once from its parameters before any engine starts: the engine
// runs (the frame's own, and the clustering geometry and clustering runs that cluster control
// adds), each run's passes in order, each neighbourhood's sigma and radius, the derived sigma_b
// and sigma_n, the grid cell and the part of the "qf+" schedule that does not wait for the
// noise estimate. Engines run a RunPlan (Engine::run_plan); the work budget and fqbench's
// neighbour statistics read the same plan, so the pass sequence is written here only.
#pragma once

#include <cstdint>
#include <vector>

#include "core/params.h"
#include "kernels/refine_plan.h"

namespace fq {

/// Every neighbourhood is the ball of radius 2 sigma around its point: the paper's cut-off of
/// its Gaussians (a weight of exp(-2) = 0.14 at the rim). The one place that says so.
inline constexpr float kRadiusPerSigma = 2.f;

/// A Gaussian's sigma and the radius its neighbourhood is cut at, in mean edges.
struct Extent {
  float sigma = 0.f;
  float radius = 0.f;
};

/// The extent of a neighbourhood of Gaussian `sigma`: radius kRadiusPerSigma * sigma.
inline Extent extent_of(float sigma) { return {sigma, kRadiusPerSigma * sigma}; }

/// The passes an engine run makes, in the order they run (pass_name: their timing names).
enum class PassKind {
  kGrid,                   ///< normalized points sorted into the grid
  kBaseQuadrics,           ///< triangle geometry, vertex -> triangle table, base quadrics
  kNeighbourhoodQuadrics,  ///< Q' within sigma_b
  kDiffusion,              ///< bilateral quadric diffusion within sigma_s (range sigma_r)
  kNoise,                  ///< "qf+": the frame's noise estimate
  kRefine,                 ///< "qf+": the refinement the estimate plans (RunPlan::refinement)
  kUpdate,                 ///< "qf": positions from the filtered quadrics (sigma_n when constrained)
  kBilateralFilter,        ///< "bf": Jones et al. 2003 within sigma_s, normals mollified within sigma_s / 2
  kScore,                  ///< clustering: representativity within sigma_d
  kLink,                   ///< clustering: quick-shift links within sigma_d
  kModes,                  ///< clustering: roots to labels
  kExportLinks,            ///< clustering: the link forest before the theta cut
};

/// The pass's name in FrameResult::timings ("grid", "neighbourhood_quadrics", ...).
const char* pass_name(PassKind kind);
/// Whether the pass visits the neighbours of each point within a radius (RunPlan::extent).
bool visits_neighbourhood(PassKind kind);

/// Which of a frame's engine runs this is (docs/ALGORITHM.md, clustering on the filtered mesh).
enum class RunRole {
  kFrame,       ///< the frame's own run: its positions are the frame's (and its labels, alone)
  kGeometry,    ///< the clustering geometry: a normal-constrained filter of the input
  kClustering,  ///< the clustering pass on the filtered positions of the run before it
};

/// One engine run: its plain parameters (no cluster control) and what they resolve to.
struct RunPlan {
  RunRole role = RunRole::kFrame;
  Params params;
  std::vector<PassKind> passes;
  /// The vertex grid's cell, and the triangle grid's of "bf" (sigma_s in both).
  float grid_cell = 0.f;
  Extent sigma_b;       ///< Q' (FilterParams::effective_sigma_b)
  Extent sigma_s;       ///< diffusion; "bf"'s spatial kernel
  Extent sigma_n;       ///< "qf" constrained: the normal smoothing (FilterParams::effective_sigma_n)
  Extent mollify;       ///< "bf": face normals mollified with sigma_s / 2 (Jones et al.)
  Extent sigma_d;       ///< score and link
  float sigma_r = 0.f;  ///< range of the diffusion and of "bf"
  float sigma_q = 0.f;  ///< range of the score and link

  bool runs(PassKind kind) const;
  /// The extent a neighbourhood pass visits (zero for the others).
  Extent extent(PassKind kind) const;
  /// "qf+": the noise the strengths come from is known before the estimate (known_noise > 0).
  bool refinement_known() const { return params.filtering.refine.known_noise > 0.f; }
  /// "qf+": the refinement for the frame's noise estimate (ignored when refinement_known()).
  RefinePlan refinement(const NoiseEstimate& estimate) const {
    return plan_refinement(params.filtering.refine, estimate);
  }
  /// "" for the frame's run, "geometry." and "cluster." for the runs cluster control adds:
  /// the prefix of their passes in the frame's timings.
  const char* timing_prefix() const;
};

/// Everything a frame runs.
struct FramePlan {
  Params params;  ///< as asked for (validated)
  /// One run, or with clustering on the filtered mesh: the frame's own filter when filtering,
  /// the geometry filter unless the frame's filter already moves the vertices as it would
  /// ("qf+", "bf", constrained "qf": only "qf" reads `constrained`), then the clustering run.
  std::vector<RunPlan> runs;
  /// The labels come from a target count, connected clusters or the filtered mesh: the runs
  /// are followed by cluster control's step (kernels/cluster_control.h).
  bool cluster_control = false;
};

/// The plan of a frame with `params`, which must be valid (validate(Params)).
FramePlan plan_frame(const Params& params);

}  // namespace fq
