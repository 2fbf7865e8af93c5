// Small float vector types shared by host and device code. Public headers use these
// instead of CUDA's float3/float4 so that they stay free of CUDA types.
#pragma once

#include <cmath>

#include "common/hd.h"

namespace fq {

struct Vec3 {
  float x, y, z;
};

/// Position in normalized units with a per-vertex scalar (the vertex area) in w:
/// one 16-byte load per neighbour on the GPU.
struct alignas(16) Point4 {
  float x, y, z, w;
};

FQ_HD Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
FQ_HD Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
FQ_HD Vec3 operator*(float s, Vec3 a) { return {s * a.x, s * a.y, s * a.z}; }
FQ_HD float dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
FQ_HD Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
FQ_HD float norm2(Vec3 a) { return dot(a, a); }
FQ_HD Point4 operator+(Point4 a, Point4 b) { return {a.x + b.x, a.y + b.y, a.z + b.z, a.w + b.w}; }
FQ_HD Point4 operator*(float s, Point4 a) { return {s * a.x, s * a.y, s * a.z, s * a.w}; }
FQ_HD Vec3 xyz(Point4 p) { return {p.x, p.y, p.z}; }
FQ_HD bool is_finite(Vec3 a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }

/// Unit vector, or zero when |a| is too small to give a direction.
FQ_HD Vec3 normalized_or_zero(Vec3 a) {
  const float n2 = norm2(a);
  if (!(n2 > 1e-30f)) return {0.f, 0.f, 0.f};
  const float inv = 1.0f / std::sqrt(n2);
  return inv * a;
}

}  // namespace fq
