// Per-vertex math of the quadric filter (paper Sec. 3), written once for both engines.
// All positions are in normalized units (mean edge length = 1), every quadric lives in
// the frame of its own vertex, and every quadric is an area-weighted *average*, so that
// sqrt(Q(v)) is an RMS distance comparable with sigma_r and sigma_q.
#pragma once

#include <cstdint>

#include "common/hd.h"
#include "kernels/gaussian.h"
#include "kernels/grid.h"
#include "kernels/quadric.h"
#include "kernels/quadric_solve.h"
#include "kernels/vec3.h"

namespace fq {

/// A weighted sum of quadrics and its weight sum; its mean is the normalized quadric.
/// Both engines build it through the *_term functions below, one neighbour at a time
/// (the CUDA team kernels split the neighbours over lanes and add the partial sums).
struct QuadricSum {
  Quadric q;
  float w;
};

FQ_HD QuadricSum zero_quadric_sum() { return {zero_quadric(), 0.f}; }

/// Weighted average; zero when no neighbour had weight.
FQ_HD Quadric mean_of(QuadricSum s) {
  if (s.w > 0.f) divide(s.q, s.w);
  return s.q;
}

/// Q' term of neighbour j (base quadric qj in j's frame, area pj.w, d = p_j - v):
/// weight a_j G_sigma_b(|d|), quadric moved to v's frame. `W` is a Gaussian or anything
/// with the same of_squared().
template <class W>
FQ_HD void add_neighbourhood_term(QuadricSum& acc, const Quadric& qj, const Point4& pj, Vec3 d, float d2,
                                  W gb) {
  const float w = pj.w * gb.of_squared(d2);
  if (!(w > 0.f)) return;
  const Vec3 t = -1.0f * d;  // v in the frame of j
  add_translated(acc.q, qj, t, evaluate(qj, t), w);
  acc.w += w;
}

/// Q^bl term of neighbour j (Q'_j = qj): spatial G_sigma_s(|d|) times range
/// G_sigma_r(sqrt(Q'_j(v))), with Q'_j(v) the squared RMS distance of v to j's planes.
template <class W>
FQ_HD void add_bilateral_term(QuadricSum& acc, const Quadric& qj, const Point4& pj, Vec3 d, float d2, W gs,
                              W gr) {
  const Vec3 t = -1.0f * d;
  const float e = evaluate(qj, t);
  const float w = pj.w * gs.of_squared(d2) * gr.of_squared(e);
  if (!(w > 0.f)) return;
  add_translated(acc.q, qj, t, e, w);
  acc.w += w;
}

/// Q'_v: average of neighbours' base quadrics weighted by a_p G_sigma_b(|v - p|) within
/// `radius` (2 sigma_b). `base[j]` is in the frame of grid point j.
FQ_HD Quadric neighbourhood_quadric(const GridView& g, const Quadric* base, uint32_t i, Gaussian gb,
                                    float radius) {
  QuadricSum acc = zero_quadric_sum();
  for_each_neighbor(g, xyz(g.points[i]), radius, [&](uint32_t j, const Point4& pj, Vec3 d, float d2) {
    add_neighbourhood_term(acc, base[j], pj, d, d2, gb);
  });
  return mean_of(acc);
}

/// Q^bl_v: bilateral diffusion of Q' with spatial G_sigma_s(|v - p|) and range
/// G_sigma_r(sqrt(Q'_p(v))) within `radius` (2 sigma_s).
FQ_HD Quadric bilateral_quadric(const GridView& g, const Quadric* nbhd, uint32_t i, Gaussian gs, Gaussian gr,
                                float radius) {
  QuadricSum acc = zero_quadric_sum();
  for_each_neighbor(g, xyz(g.points[i]), radius, [&](uint32_t j, const Point4& pj, Vec3 d, float d2) {
    add_bilateral_term(acc, nbhd[j], pj, d, d2, gs, gr);
  });
  return mean_of(acc);
}

/// Area-weighted vertex normals smoothed by G_sigma_n within `radius` (2 sigma_n);
/// `normals[j]` are unnormalized area-weighted sums of incident face normals.
FQ_HD Vec3 smoothed_normal(const GridView& g, const Vec3* normals, uint32_t i, Gaussian gn, float radius) {
  const Vec3 x = xyz(g.points[i]);
  Vec3 acc{0.f, 0.f, 0.f};
  for_each_neighbor(g, x, radius, [&](uint32_t j, const Point4&, Vec3, float d2) {
    acc = acc + gn.of_squared(d2) * normals[j];
  });
  return normalized_or_zero(acc);
}

/// New position of vertex i from its filtered quadric (unconstrained or along `normal`).
FQ_HD Vec3 updated_position(Vec3 x, const Quadric& qbl, bool constrained, Vec3 normal, float tikhonov_eps) {
  const Vec3 step =
      constrained ? constrained_step(qbl, normal, tikhonov_eps) : minimizer_step(qbl, tikhonov_eps);
  return x + step;
}

}  // namespace fq
