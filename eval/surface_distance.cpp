#include "eval/surface_distance.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "eval/error_metrics.h"
#include "eval/triangle_index.h"
#include "kernels/frame_prep.h"

namespace fq {

SurfaceDistance distance_to_surface(const MeshView& reference, const float* points, uint32_t num_points) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  // The same scale as rmse_over_diagonal, so the two measures compare.
  const double diag = bbox_diagonal(reference);
  const double edge = mean_edge_length(reference);
  if (reference.num_triangles == 0 || num_points == 0 || !(diag > 0.0) || !(edge > 0.0)) return {kNaN, kNaN};
  const TriangleIndex index(reference, 2.0 * edge);
  double sum2 = 0.0, dmax = 0.0;
  for (uint32_t i = 0; i < num_points; ++i) {
    const float* p = points + 3 * size_t(i);
    const double d = index.closest({p[0], p[1], p[2]}, index.max_reach() + edge).distance;
    sum2 += d * d;
    dmax = std::max(dmax, d);
  }
  return {std::sqrt(sum2 / num_points) / diag, dmax / diag};
}

}  // namespace fq
