// Error quadric Q(y) = y^T A y + 2 b.y + c in the local frame of the vertex that owns it
// (y = x - vertex position, normalized units). Local frames keep c small: evaluating a
// quadric next to its vertex never subtracts large numbers, which is what makes float32
// enough (a global frame would put c ~ coordinate^2 and lose the result to cancellation).
#pragma once

#include "common/hd.h"
#include "kernels/vec3.h"

namespace fq {

/// Symmetric 4x4 quadric in 10 floats: A (upper triangle), b, c.
struct Quadric {
  float a00, a01, a02, a11, a12, a22;
  float b0, b1, b2;
  float c;
};

FQ_HD Quadric zero_quadric() { return {0, 0, 0, 0, 0, 0, 0, 0, 0, 0}; }

/// Quadric of squared distance to the plane through `point` with unit normal `n`,
/// expressed in the frame whose origin is `origin`.
FQ_HD Quadric plane_quadric(Vec3 n, Vec3 point, Vec3 origin) {
  const float d = dot(n, origin - point);  // signed distance of the origin to the plane
  return {n.x * n.x, n.x * n.y, n.x * n.z, n.y * n.y, n.y * n.z, n.z * n.z, d * n.x, d * n.y, d * n.z, d * d};
}

FQ_HD Vec3 mul_a(const Quadric& q, Vec3 y) {
  return {q.a00 * y.x + q.a01 * y.y + q.a02 * y.z, q.a01 * y.x + q.a11 * y.y + q.a12 * y.z,
          q.a02 * y.x + q.a12 * y.y + q.a22 * y.z};
}

FQ_HD Vec3 b_of(const Quadric& q) { return {q.b0, q.b1, q.b2}; }

FQ_HD float trace_a(const Quadric& q) { return q.a00 + q.a11 + q.a22; }

/// Q(y); clamped at zero because a sum of squared distances is never negative and
/// rounding may push it slightly below.
FQ_HD float evaluate(const Quadric& q, Vec3 y) {
  const float v = dot(y, mul_a(q, y)) + 2.0f * dot(b_of(q), y) + q.c;
  return v > 0.f ? v : 0.f;
}

/// acc += w * q
FQ_HD void add_scaled(Quadric& acc, const Quadric& q, float w) {
  acc.a00 += w * q.a00;
  acc.a01 += w * q.a01;
  acc.a02 += w * q.a02;
  acc.a11 += w * q.a11;
  acc.a12 += w * q.a12;
  acc.a22 += w * q.a22;
  acc.b0 += w * q.b0;
  acc.b1 += w * q.b1;
  acc.b2 += w * q.b2;
  acc.c += w * q.c;
}

/// acc += w * (q moved to a frame whose origin is at `t` in q's frame). Moving the
/// origin keeps A, shifts b by A t and makes c the value at t (which the caller often
/// already has: `value_at_t` = evaluate(q, t)).
FQ_HD void add_translated(Quadric& acc, const Quadric& q, Vec3 t, float value_at_t, float w) {
  const Vec3 at = mul_a(q, t);
  acc.a00 += w * q.a00;
  acc.a01 += w * q.a01;
  acc.a02 += w * q.a02;
  acc.a11 += w * q.a11;
  acc.a12 += w * q.a12;
  acc.a22 += w * q.a22;
  acc.b0 += w * (q.b0 + at.x);
  acc.b1 += w * (q.b1 + at.y);
  acc.b2 += w * (q.b2 + at.z);
  acc.c += w * value_at_t;
}

/// q /= s, component by component. Normalizing a weighted sum by its weight sum this way
/// stays finite when the sum is denormal (1/s would overflow to inf; each component is
/// at most s times a finite value, so the quotient is finite).
FQ_HD void divide(Quadric& q, float s) {
  q.a00 /= s;
  q.a01 /= s;
  q.a02 /= s;
  q.a11 /= s;
  q.a12 /= s;
  q.a22 /= s;
  q.b0 /= s;
  q.b1 /= s;
  q.b2 /= s;
  q.c /= s;
}

}  // namespace fq
