// Per-vertex math of quadric quick shift (paper Sec. 4, Alg. 1 and 2).
//
// Branch cutting: Algorithm 1 as printed cuts a link when p < theta, which would give
// *more* clusters at higher theta; the paper's own Table 3 and Fig. 15 show fewer. We cut
// when p < 1 - theta, which reproduces them (bunny, Table 3 row: 89 clusters in the paper).
#pragma once

#include <cstdint>

#include "gaussian.h"
#include "grid.h"
#include "hd.h"
#include "quadric.h"
#include "vec3.h"

namespace fq {

/// S_v: how well Q^bl_v explains v's neighbourhood (radius 2 sigma_d):
/// sum a_i G_sigma_d(|v - v_i|) G_sigma_q(sqrt(Q^bl_v(v_i))) / sum a_i. With `euclidean`
/// the range term is dropped (plain Parzen density: the paper's Fig. 17 baseline).
FQ_HD float representativity(const GridView& g, const Quadric* qbl, uint32_t i, Gaussian gd,
                             Gaussian gq, float radius, bool euclidean) {
  const Vec3 x = xyz(g.points[i]);
  const Quadric qi = qbl[i];
  float num = 0.f, den = 0.f;
  for_each_neighbor(g, x, radius, [&](uint32_t, const Point4& pj, Vec3 d, float d2) {
    den += pj.w;
    float w = pj.w * gd.of_squared(d2);
    if (!euclidean) w *= gq.of_squared(evaluate(qi, d));
    num += w;
  });
  return den > 0.f ? num / den : 0.f;
}

/// Strict total order used for linking: by score, ties broken by index, so links can
/// never form a cycle even where symmetric meshes give equal scores.
FQ_HD bool ranks_above(float sj, uint32_t j, float si, uint32_t i) {
  return sj > si || (sj == si && j > i);
}

/// Alg. 1: link i to the higher-ranked neighbour maximizing
/// p(v, v_i) = G_sigma_d(|v - v_i|) G_sigma_q(sqrt(Q^bl_{v_i}(v))); i itself (a root) when
/// there is none or the best proximity is below `cut` (= 1 - theta).
FQ_HD uint32_t quick_shift_link(const GridView& g, const Quadric* qbl, const float* score,
                                uint32_t i, Gaussian gd, Gaussian gq, float radius,
                                bool euclidean, float cut) {
  const Vec3 x = xyz(g.points[i]);
  const float si = score[i];
  uint32_t best = i;
  float pmax = 0.f;
  for_each_neighbor(g, x, radius, [&](uint32_t j, const Point4&, Vec3 d, float d2) {
    if (j == i || !ranks_above(score[j], j, si, i)) return;
    float p = gd.of_squared(d2);
    if (!euclidean) p *= gq.of_squared(evaluate(qbl[j], -1.0f * d));
    if (p > pmax) {
      pmax = p;
      best = j;
    }
  });
  return pmax < cut ? i : best;
}

/// Alg. 2: follow links to the root (terminates: links strictly climb the rank order).
FQ_HD uint32_t find_root(const uint32_t* next, uint32_t i) {
  uint32_t cur = i;
  for (uint32_t parent = next[cur]; parent != cur; parent = next[cur]) cur = parent;
  return cur;
}

}  // namespace fq
