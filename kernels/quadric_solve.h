// Minimizers of a quadric around its own origin (the current vertex position).
//
// The paper moves a vertex to the quadric minimizer -A^{-1} b. In flat and cylindrical
// regions A is singular and that point runs off along the flat directions; on the clean
// fandisk a plain eigenvalue cut at 1e-3 of the largest still moved the median vertex 1.8
// mean edges. We therefore solve the Tikhonov-regularized system
//     (A + eps * tr(A)/3 * I) step = -b
// which pulls toward the current position, and additionally drop directions whose
// eigenvalue is below `kRankEps` of the largest (this only matters when eps == 0).
#pragma once

#include <cmath>

#include "common/hd.h"
#include "kernels/quadric.h"
#include "kernels/sym3_eigen.h"
#include "kernels/vec3.h"

namespace fq {

inline constexpr float kRankEps = 1e-3f;
/// A quadric whose trace is below this carries no geometric information (no area nearby).
inline constexpr float kMinTrace = 1e-12f;

/// Step from the origin of q's frame to its regularized minimizer. Always finite.
FQ_HD Vec3 minimizer_step(const Quadric& q, float tikhonov_eps) {
  const float tr = trace_a(q);
  if (!(tr > kMinTrace)) return {0.f, 0.f, 0.f};
  const float reg = tikhonov_eps * tr / 3.0f;
  const Sym3Eigen e = sym3_eigen(q.a00, q.a01, q.a02, q.a11, q.a12, q.a22);
  const float lmax = fmaxf(e.values[0], fmaxf(e.values[1], e.values[2]));
  Vec3 step{0.f, 0.f, 0.f};
  FQ_UNROLL
  for (int k = 0; k < 3; ++k) {
    const float denom = e.values[k] + reg;
    if (!(denom > kRankEps * (lmax + reg))) continue;
    const Vec3 ek{e.vectors[0][k], e.vectors[1][k], e.vectors[2][k]};
    const float coef = -dot(ek, b_of(q)) / denom;
    step = step + coef * ek;
  }
  return is_finite(step) ? step : Vec3{0.f, 0.f, 0.f};
}

/// Step along unit direction n minimizing q on the line origin + lambda n (the paper's
/// normal-constrained mode), with the same regularization of the curvature n^T A n.
FQ_HD Vec3 constrained_step(const Quadric& q, Vec3 n, float tikhonov_eps) {
  const float tr = trace_a(q);
  if (!(tr > kMinTrace) || !(norm2(n) > 0.5f)) return {0.f, 0.f, 0.f};
  const float denom = dot(n, mul_a(q, n)) + tikhonov_eps * tr / 3.0f;
  if (!(denom > kRankEps * tr)) return {0.f, 0.f, 0.f};
  const float lambda = -dot(b_of(q), n) / denom;
  const Vec3 step = lambda * n;
  return is_finite(step) ? step : Vec3{0.f, 0.f, 0.f};
}

}  // namespace fq
