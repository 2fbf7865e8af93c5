// A quadric stored as three 16-byte words for the team kernels' neighbour loads: three
// 128-bit loads through the read-only path instead of ten 32-bit ones (Quadric itself is
// 40 bytes with 4-byte alignment). Only the layout differs; the math takes Quadric.
#pragma once

#include <cuda_runtime.h>

#include <cstdint>

#include "kernels/quadric.h"
#include "kernels/vec3.h"

namespace fq::cuda {

struct alignas(16) PackedQuadric {
  float4 w0;  ///< a00 a01 a02 a11
  float4 w1;  ///< a12 a22 b0 b1
  float4 w2;  ///< b2 c 0 0
};

__device__ __forceinline__ PackedQuadric pack(const Quadric& q) {
  return {{q.a00, q.a01, q.a02, q.a11}, {q.a12, q.a22, q.b0, q.b1}, {q.b2, q.c, 0.f, 0.f}};
}

__device__ __forceinline__ Quadric load_quadric(const PackedQuadric* a, uint32_t j) {
  const float4 w0 = __ldg(&a[j].w0), w1 = __ldg(&a[j].w1), w2 = __ldg(&a[j].w2);
  return {w0.x, w0.y, w0.z, w0.w, w1.x, w1.y, w1.z, w1.w, w2.x, w2.y};
}

__device__ __forceinline__ Point4 load_point(const Point4* p, uint32_t j) {
  const float4 v = __ldg(reinterpret_cast<const float4*>(p) + j);
  return {v.x, v.y, v.z, v.w};
}

}  // namespace fq::cuda
