// Per-vertex math of the baseline bilateral mesh filter of Jones, Durand and Desbrun
// (SIGGRAPH 2003), the paper's "BF": each nearby triangle predicts the vertex by projecting
// it on its plane (centroid, mollified normal); predictions are averaged with weights
// a_t G_sigma_s(|v - c_t|) G_sigma_r(|v - P_t(v)|).
#pragma once

#include <cstdint>

#include "common/hd.h"
#include "kernels/gaussian.h"
#include "kernels/grid.h"
#include "kernels/vec3.h"

namespace fq {

/// Mollified face normal: area- and G_sigma-weighted average of nearby face normals
/// (the grid holds triangle centroids with w = area). The paper uses sigma = sigma_s / 2.
FQ_HD Vec3 mollified_face_normal(const GridView& tg, const Vec3* face_normals, uint32_t t, Gaussian g,
                                 float radius) {
  const Vec3 c = xyz(tg.points[t]);
  Vec3 acc{0.f, 0.f, 0.f};
  for_each_neighbor(tg, c, radius, [&](uint32_t j, const Point4& pj, Vec3, float d2) {
    acc = acc + (pj.w * g.of_squared(d2)) * face_normals[j];
  });
  return normalized_or_zero(acc);
}

/// Jones et al.'s filtered position of the vertex at x.
FQ_HD Vec3 jones_bilateral_position(const GridView& tg, const Vec3* mollified_normals, Vec3 x, Gaussian gs,
                                    Gaussian gr, float radius) {
  Vec3 acc{0.f, 0.f, 0.f};
  float wsum = 0.f;
  for_each_neighbor(tg, x, radius, [&](uint32_t j, const Point4& pj, Vec3 d, float d2) {
    const Vec3 n = mollified_normals[j];
    const float h = dot(d, n);  // (c_t - v).n: the prediction is v + h n
    const float w = pj.w * gs.of_squared(d2) * gr.of_squared(h * h);
    if (!(w > 0.f)) return;
    acc = acc + (w * h) * n;
    wsum += w;
  });
  // Divide rather than multiply by 1/wsum: wsum may be denormal when sigma_r is tiny.
  return wsum > 0.f ? Vec3{x.x + acc.x / wsum, x.y + acc.y / wsum, x.z + acc.z / wsum} : x;
}

}  // namespace fq
