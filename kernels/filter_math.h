// Per-vertex math of the quadric filter (paper Sec. 3), written once for both engines.
// All positions are in normalized units (mean edge length = 1), every quadric lives in
// the frame of its own vertex, and every quadric is an area-weighted *average*, so that
// sqrt(Q(v)) is an RMS distance comparable with sigma_r and sigma_q.
#pragma once

#include <cstdint>

#include "gaussian.h"
#include "grid.h"
#include "hd.h"
#include "quadric.h"
#include "quadric_solve.h"
#include "vec3.h"

namespace fq {

/// Q'_v: average of neighbours' base quadrics weighted by a_p G_sigma_b(|v - p|) within
/// `radius` (2 sigma_b). `base[j]` is in the frame of grid point j.
FQ_HD Quadric neighbourhood_quadric(const GridView& g, const Quadric* base, uint32_t i,
                                    Gaussian gb, float radius) {
  const Vec3 x = xyz(g.points[i]);
  Quadric acc = zero_quadric();
  float wsum = 0.f;
  for_each_neighbor(g, x, radius, [&](uint32_t j, const Point4& pj, Vec3 d, float d2) {
    const float w = pj.w * gb.of_squared(d2);
    if (!(w > 0.f)) return;
    const Vec3 t = -1.0f * d;  // x in the frame of j
    add_translated(acc, base[j], t, evaluate(base[j], t), w);
    wsum += w;
  });
  if (wsum > 0.f) divide(acc, wsum);
  return acc;
}

/// Q^bl_v: bilateral diffusion of Q' with spatial G_sigma_s(|v - p|) and range
/// G_sigma_r(sqrt(Q'_p(v))) within `radius` (2 sigma_s).
FQ_HD Quadric bilateral_quadric(const GridView& g, const Quadric* nbhd, uint32_t i, Gaussian gs,
                                Gaussian gr, float radius) {
  const Vec3 x = xyz(g.points[i]);
  Quadric acc = zero_quadric();
  float wsum = 0.f;
  for_each_neighbor(g, x, radius, [&](uint32_t j, const Point4& pj, Vec3 d, float d2) {
    const Vec3 t = -1.0f * d;
    const float e = evaluate(nbhd[j], t);  // Q'_p(v): squared RMS distance of v to p's planes
    const float w = pj.w * gs.of_squared(d2) * gr.of_squared(e);
    if (!(w > 0.f)) return;
    add_translated(acc, nbhd[j], t, e, w);
    wsum += w;
  });
  if (wsum > 0.f) divide(acc, wsum);
  return acc;
}

/// Area-weighted vertex normals smoothed by G_sigma_n within `radius` (2 sigma_n);
/// `normals[j]` are unnormalized area-weighted sums of incident face normals.
FQ_HD Vec3 smoothed_normal(const GridView& g, const Vec3* normals, uint32_t i, Gaussian gn,
                           float radius) {
  const Vec3 x = xyz(g.points[i]);
  Vec3 acc{0.f, 0.f, 0.f};
  for_each_neighbor(g, x, radius, [&](uint32_t j, const Point4&, Vec3, float d2) {
    acc = acc + gn.of_squared(d2) * normals[j];
  });
  return normalized_or_zero(acc);
}

/// New position of vertex i from its filtered quadric (unconstrained or along `normal`).
FQ_HD Vec3 updated_position(Vec3 x, const Quadric& qbl, bool constrained, Vec3 normal,
                            float tikhonov_eps) {
  const Vec3 step = constrained ? constrained_step(qbl, normal, tikhonov_eps)
                                : minimizer_step(qbl, tikhonov_eps);
  return x + step;
}

}  // namespace fq
