// Per-vertex math of quadric quick shift (paper Sec. 4, Alg. 1 and 2).
//
// Branch cutting: Algorithm 1 as printed cuts a link when p < theta, which would give
// *more* clusters at higher theta; the paper's own Table 3 and Fig. 15 show fewer. We cut
// when p < 1 - theta, which reproduces them (bunny, Table 3 row: 89 clusters in the paper).
#pragma once

#include <cstdint>

#include "common/hd.h"
#include "kernels/gaussian.h"
#include "kernels/grid.h"
#include "kernels/quadric.h"
#include "kernels/vec3.h"

namespace fq {

/// Numerator and denominator of a representativity score.
struct ScoreSum {
  float num, den;
};

/// S_v term of neighbour j (d = v_j - v, area pj.w): a_j G_sigma_d(|d|) G_sigma_q(sqrt(Q^bl_v(v_j)))
/// over a_j. With `euclidean` the range term is dropped (plain Parzen density: the paper's
/// Fig. 17 baseline). `W` is a Gaussian or anything with the same of_squared().
template <class W>
FQ_HD void add_score_term(ScoreSum& acc, const Quadric& qi, const Point4& pj, Vec3 d, float d2, W gd, W gq,
                          bool euclidean) {
  acc.den += pj.w;
  float w = pj.w * gd.of_squared(d2);
  if (!euclidean) w *= gq.of_squared(evaluate(qi, d));
  acc.num += w;
}

FQ_HD float score_of(ScoreSum s) { return s.den > 0.f ? s.num / s.den : 0.f; }

/// S_v: how well Q^bl_v explains v's neighbourhood (radius 2 sigma_d).
FQ_HD float representativity(const GridView& g, const Quadric* qbl, uint32_t i, Gaussian gd, Gaussian gq,
                             float radius, bool euclidean) {
  const Quadric qi = qbl[i];
  ScoreSum acc{0.f, 0.f};
  for_each_neighbor(g, xyz(g.points[i]), radius, [&](uint32_t, const Point4& pj, Vec3 d, float d2) {
    add_score_term(acc, qi, pj, d, d2, gd, gq, euclidean);
  });
  return score_of(acc);
}

/// Strict total order used for linking: by score, ties broken by index, so links can
/// never form a cycle even where symmetric meshes give equal scores.
FQ_HD bool ranks_above(float sj, uint32_t j, float si, uint32_t i) { return sj > si || (sj == si && j > i); }

/// p(v, v_j) = G_sigma_d(|v - v_j|) G_sigma_q(sqrt(Q^bl_{v_j}(v))), d = v_j - v, qj = Q^bl_{v_j}.
template <class W>
FQ_HD float link_proximity(const Quadric& qj, Vec3 d, float d2, W gd, W gq, bool euclidean) {
  float p = gd.of_squared(d2);
  if (!euclidean) p *= gq.of_squared(evaluate(qj, -1.0f * d));
  return p;
}

/// The best link so far: the first j (in visiting order) with the largest proximity.
struct LinkBest {
  float p;
  uint32_t j;
  FQ_HD void offer(float pj, uint32_t jj) {
    if (pj > p) {
      p = pj;
      j = jj;
    }
  }
  /// Alg. 1's branch cut: vertex i stays a root when no link reaches `cut` (= 1 - theta).
  FQ_HD uint32_t target(uint32_t i, float cut) const { return p < cut ? i : j; }
};

/// Alg. 1: link i to the higher-ranked neighbour maximizing p(v, v_i); i itself (a root)
/// when there is none or the best proximity is below `cut` (= 1 - theta).
FQ_HD uint32_t quick_shift_link(const GridView& g, const Quadric* qbl, const float* score, uint32_t i,
                                Gaussian gd, Gaussian gq, float radius, bool euclidean, float cut) {
  const float si = score[i];
  LinkBest best{0.f, i};
  for_each_neighbor(g, xyz(g.points[i]), radius, [&](uint32_t j, const Point4&, Vec3 d, float d2) {
    if (j == i || !ranks_above(score[j], j, si, i)) return;
    best.offer(link_proximity(qbl[j], d, d2, gd, gq, euclidean), j);
  });
  return best.target(i, cut);
}

/// Alg. 2: follow links to the root (terminates: links strictly climb the rank order).
FQ_HD uint32_t find_root(const uint32_t* next, uint32_t i) {
  uint32_t cur = i;
  for (uint32_t parent = next[cur]; parent != cur; parent = next[cur]) cur = parent;
  return cur;
}

}  // namespace fq
