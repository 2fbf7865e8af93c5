// One vertex of the exported link forest (FrameResult::link_parent / link_p), written once
// for both engines: the link target in input numbering and the proximity p that Alg. 1's
// cut compares with 1 - theta, recomputed for that one link by the link pass's own math.
#pragma once

#include <cstdint>

#include "kernels/cluster_math.h"

namespace fq {

/// Sorted vertex k links to sorted next[k]; `order` maps sorted -> input indices.
FQ_HD void export_link(const Point4* points, const Quadric* qbl, const uint32_t* next, const uint32_t* order,
                       uint32_t k, Gaussian gd, Gaussian gq, bool euclidean, uint32_t& parent, float& p) {
  const uint32_t j = next[k];
  parent = order[j];
  if (j == k) {
    p = 1.f;  // a root at every theta
    return;
  }
  const Vec3 d = xyz(points[j]) - xyz(points[k]);
  p = link_proximity(qbl[j], d, dot(d, d), gd, gq, euclidean);
}

}  // namespace fq
