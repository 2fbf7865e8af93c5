// The passes of one "qf+" refinement run (kernels/refine_math.h), as both engines loop them:
// the fine run after QF, and the rough-input run on the input itself (step 5). Host only.
#pragma once

#include "kernels/gaussian.h"
#include "core/params.h"

namespace fq {

struct RefineSchedule {
  int relax_iterations;
  float relax_step;
  float feature_ratio;
  int rounds;  ///< face normals filtered and vertices updated, this many times over
  int normal_iterations;
  Gaussian gs, gr;
  int vertex_iterations;
  float tangential_step;
};

inline RefineSchedule fine_schedule(const RefineParams& r) {
  return {r.relax_iterations, r.relax_step, r.feature_ratio, 1, r.normal_iterations,
          Gaussian::with_sigma(r.normal_sigma_s), Gaussian::with_sigma(r.normal_sigma_r), r.vertex_iterations,
          r.tangential_step};
}

// No relaxation: it opens the folds QF leaves, and this run starts from the input (on the
// dragon at noise 0.3 it also measured better without: 0.1939 against 0.1942 rad).
inline RefineSchedule rough_schedule(const RefineParams& r) {
  return {0, r.relax_step, r.feature_ratio, r.rough_rounds, r.normal_iterations,
          Gaussian::with_sigma(r.normal_sigma_s), Gaussian::with_sigma(r.rough_normal_sigma_r),
          r.rough_vertex_iterations, r.tangential_step};
}

/// Whether the rough-input run can be needed at all (step 5 on, and the guard measuring r).
inline bool rough_path_on(const RefineParams& r) { return r.rough_full > 0.f && r.full_above > 0.f; }

}  // namespace fq
