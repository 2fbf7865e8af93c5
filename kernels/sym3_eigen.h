// Eigen-decomposition of a symmetric 3x3 matrix by cyclic Jacobi rotations.
// Fixed sweep count and compile-time indices: branch-light, register-resident on the GPU,
// and bit-identical on every thread of the CPU engine.
#pragma once

#include <cmath>

#include "common/hd.h"

namespace fq {

struct Sym3Eigen {
  float values[3];
  float vectors[3][3];  // vectors[r][k]: component r of eigenvector k
};

namespace detail {

template <int P, int Q, int R>
FQ_HD void jacobi_rotate(float (&m)[3][3], float (&v)[3][3]) {
  const float apq = m[P][Q];
  if (!(std::fabs(apq) > 1e-30f)) return;
  const float theta = (m[Q][Q] - m[P][P]) / (2.0f * apq);
  const float t = (theta >= 0.f ? 1.f : -1.f) / (std::fabs(theta) + std::sqrt(theta * theta + 1.0f));
  const float c = 1.0f / std::sqrt(t * t + 1.0f);
  const float s = t * c;
  m[P][P] -= t * apq;
  m[Q][Q] += t * apq;
  m[P][Q] = m[Q][P] = 0.f;
  const float arp = m[R][P], arq = m[R][Q];
  m[R][P] = m[P][R] = c * arp - s * arq;
  m[R][Q] = m[Q][R] = s * arp + c * arq;
  FQ_UNROLL
  for (int r = 0; r < 3; ++r) {
    const float vp = v[r][P], vq = v[r][Q];
    v[r][P] = c * vp - s * vq;
    v[r][Q] = s * vp + c * vq;
  }
}

}  // namespace detail

/// Jacobi converges quadratically; 6 sweeps take any float32 3x3 to rounding level.
FQ_HD Sym3Eigen sym3_eigen(float a00, float a01, float a02, float a11, float a12, float a22) {
  float m[3][3] = {{a00, a01, a02}, {a01, a11, a12}, {a02, a12, a22}};
  Sym3Eigen e{{0, 0, 0}, {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  FQ_UNROLL
  for (int sweep = 0; sweep < 6; ++sweep) {
    detail::jacobi_rotate<0, 1, 2>(m, e.vectors);
    detail::jacobi_rotate<0, 2, 1>(m, e.vectors);
    detail::jacobi_rotate<1, 2, 0>(m, e.vectors);
  }
  e.values[0] = m[0][0];
  e.values[1] = m[1][1];
  e.values[2] = m[2][2];
  return e;
}

}  // namespace fq
