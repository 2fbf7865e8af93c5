// Distance from a candidate's vertices to the reference *surface*. Vertex RMSE (metrics.h)
// also counts motion along the surface, which the unconstrained quadric filter does by
// design (vertices slide toward features, paper Fig. 5); this measure does not, so the two
// together separate "left the surface" from "moved along it".
#pragma once

#include "core/mesh_view.h"

namespace fq {

struct SurfaceDistance {
  double rms_over_diagonal = 0.0;  ///< sqrt(mean d^2) / reference bbox diagonal
  double max_over_diagonal = 0.0;  ///< max d / diagonal (one-sided Hausdorff)
};

/// For every candidate vertex (3 floats each, `num_points` of them) the exact distance to
/// the closest point of any reference triangle. NaN fields when the reference has no
/// non-degenerate extent.
SurfaceDistance distance_to_surface(const MeshView& reference, const float* points, uint32_t num_points);

}  // namespace fq
