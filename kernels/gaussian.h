// Unnormalized Gaussian kernel G_sigma(x) = exp(-x^2 / (2 sigma^2)), so G(0) = 1 and the
// products of kernels used as proximities (quick shift) lie in (0, 1].
#pragma once

#include <cmath>

#include "common/hd.h"

namespace fq {

/// Precomputed -1 / (2 sigma^2) so the hot loops do one multiply and one exp.
struct Gaussian {
  float neg_inv_two_sigma2;

  static Gaussian with_sigma(float sigma) { return {-1.0f / (2.0f * sigma * sigma)}; }
  FQ_HD float of_squared(float x2) const { return std::exp(x2 * neg_inv_two_sigma2); }
};

}  // namespace fq
