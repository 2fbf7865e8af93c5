// The rigid part of a motion over a vertex's neighbourhood, from ring means (track A,
// kernels/temporal_ids.h; written once for the CPU and the CUDA engine).
//
// A ring mean of the id displacement d = x - a reproduces a motion that is affine along the
// surface, but a rotation is affine in space, not along a curved surface: the mean of a limb's
// rotating points lies inside the limb, and their mean displacement is the rotation of that
// inner point, not of the vertex. The error is (Rot - I)(ā - a_v), the rotation applied to the
// ring mean's shrinkage, and it grows with the rotation and the curvature: on crane it was
// about 0.034 mean edges along the normals, most of what the motion estimate left besides the
// noise, and what the average then took for noise and pulled towards. The fix is the rigid
// motion that fits the neighbourhood best (Kabsch's): with the same weights W as the ring means,
// S = Σ W (x_u - x̄)(a_u - ā)ᵀ, Rot the rotation nearest S, and the vertex moved by Rot (a_v - ā) +
// x̄. That is the ring mean's motion x̄ - ā plus the correction (Rot - I)(a_v - ā), computed from
// ring means of a's coordinates and of the products x_i a_j: the same passes as the motion's.
// A rotation fitted to some sixty noisy points is far steadier than the points (the noise moves
// the correction by about a fortieth of itself on crane), so the correction adds no noise to speak of.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "common/hd.h"
#include "kernels/sym3_eigen.h"
#include "kernels/vec3.h"

namespace fq {

/// What the ring means of a vertex's neighbourhood need for its rigid motion: the last
/// averaged position p (mean edges, from an origin shared by the frame) and the nine products
/// x_i p_j with the frame's position x = p + d, packed four to a lane.
struct RigidInputs {
  Point4 p;   ///< p.x, p.y, p.z, x.x p.x
  Point4 q0;  ///< x.x p.y, x.x p.z, x.y p.x, x.y p.y
  Point4 q1;  ///< x.y p.z, x.z p.x, x.z p.y, x.z p.z
};

/// A vertex's displacement d = x - a from the last averaged input and that input's position p
/// from the frame's `origin`, both in mean edges (`unit` per input unit): what the step reads of
/// vertex v of x and a (3 floats a vertex, input units), the same on both engines.
struct IdPoint {
  Vec3 d, p;
};
FQ_HD IdPoint id_point(const float* x, const float* a, uint32_t v, float unit, Vec3 origin) {
  const size_t i = 3 * size_t(v);
  return {unit * Vec3{x[i] - a[i], x[i + 1] - a[i + 1], x[i + 2] - a[i + 2]},
          unit * Vec3{a[i] - origin.x, a[i + 1] - origin.y, a[i + 2] - origin.z}};
}

/// The ring means' inputs at a vertex at p (last averaged input) displaced by d.
FQ_HD RigidInputs rigid_inputs(Vec3 p, Vec3 d) {
  const Vec3 x = p + d;
  return {Point4{p.x, p.y, p.z, x.x * p.x}, Point4{x.x * p.y, x.x * p.z, x.y * p.x, x.y * p.y},
          Point4{x.y * p.z, x.z * p.x, x.z * p.y, x.z * p.z}};
}

/// Below this share of the largest, the second singular value of S leaves the rotation about
/// the neighbourhood's long axis unsettled (a strip of triangles, a neighbourhood on a line):
/// the ring mean's motion stands alone there.
constexpr float kRigidRankShare = 1e-4f;

/// The rigid correction of a vertex at p (its last averaged position): (Rot - I)(p - ā), with
/// `mean` the ring means of rigid_inputs over its neighbourhood and `motion` the same ring
/// means of d (x̄ - ā). Rot is the rotation nearest S = mean(x pᵀ) - x̄ āᵀ: from the two largest
/// eigenvectors v1, v2 of SᵀS and u_k = S v_k (then orthonormalized), Rot = u1 v1ᵀ + u2 v2ᵀ +
/// (u1 × u2)(v1 × v2)ᵀ, which is Kabsch's rotation with its reflection fix (a flat
/// neighbourhood, whose third singular value is 0, included). Zero where S has no rank two.
FQ_HD Vec3 rigid_correction(const RigidInputs& mean, Vec3 motion, Vec3 p) {
  const Vec3 ab = xyz(mean.p);
  const Vec3 xb = ab + motion;
  // S_ij = mean(x_i p_j) - x̄_i ā_j.
  const float s00 = mean.p.w - xb.x * ab.x, s01 = mean.q0.x - xb.x * ab.y, s02 = mean.q0.y - xb.x * ab.z;
  const float s10 = mean.q0.z - xb.y * ab.x, s11 = mean.q0.w - xb.y * ab.y, s12 = mean.q1.x - xb.y * ab.z;
  const float s20 = mean.q1.y - xb.z * ab.x, s21 = mean.q1.z - xb.z * ab.y, s22 = mean.q1.w - xb.z * ab.z;
  // SᵀS (columns of S dotted).
  const Vec3 c0{s00, s10, s20}, c1{s01, s11, s21}, c2{s02, s12, s22};
  const Sym3Eigen e =
      sym3_eigen(dot(c0, c0), dot(c0, c1), dot(c0, c2), dot(c1, c1), dot(c1, c2), dot(c2, c2));
  // The two largest eigenvalues' indices.
  int i1 = 0;
  if (e.values[1] > e.values[i1]) i1 = 1;
  if (e.values[2] > e.values[i1]) i1 = 2;
  int i2 = i1 == 0 ? 1 : 0;
  for (int k = 0; k < 3; ++k)
    if (k != i1 && e.values[k] > e.values[i2]) i2 = k;
  const float l1 = e.values[i1], l2 = e.values[i2];
  if (!(l1 > 0.f) || !(l2 > kRigidRankShare * l1)) return Vec3{0.f, 0.f, 0.f};
  const Vec3 v1{e.vectors[0][i1], e.vectors[1][i1], e.vectors[2][i1]};
  const Vec3 v2{e.vectors[0][i2], e.vectors[1][i2], e.vectors[2][i2]};
  const auto apply = [&](Vec3 v) {
    return Vec3{s00 * v.x + s01 * v.y + s02 * v.z, s10 * v.x + s11 * v.y + s12 * v.z,
                s20 * v.x + s21 * v.y + s22 * v.z};
  };
  const Vec3 u1 = normalized_or_zero(apply(v1));
  const Vec3 w2 = apply(v2);
  const Vec3 u2 = normalized_or_zero(w2 - dot(u1, w2) * u1);
  if (!(norm2(u1) > 0.f) || !(norm2(u2) > 0.f)) return Vec3{0.f, 0.f, 0.f};
  const Vec3 q = p - ab;
  const Vec3 rotated = dot(v1, q) * u1 + dot(v2, q) * u2 + dot(cross(v1, v2), q) * cross(u1, u2);
  return rotated - q;
}

}  // namespace fq
