// Synthetic capture frames of one object, for label-tracking experiments: each frame is the
// clean mesh turned about the vertical axis, with its own noise and its own vertex order
// (real capture frames share no vertex ids).
#pragma once

#include <cstdint>

#include "core/mesh_view.h"

namespace fq {

/// `clean` rotated by `degrees` about the y axis through its bounding-box centre, then
/// Gaussian noise of `noise_sigma` mean edges (eval/noise.h, `seed`), then its vertices
/// shuffled (seeded by `seed` too) with the triangles renumbered to match.
Mesh capture_frame(const Mesh& clean, double degrees, double noise_sigma, uint64_t seed);

}  // namespace fq
