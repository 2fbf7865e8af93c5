// Floats mapped to ints of the same order, so that integer atomicMin/atomicMax reduce float
// bounds across blocks (exact: min and max need no rounding).
#pragma once

#include <cstring>

namespace fq::cuda {

__device__ __forceinline__ int ordered_int(float f) {
  const int i = __float_as_int(f);
  return i >= 0 ? i : i ^ 0x7fffffff;
}

inline float from_ordered_int(int i) {
  const int bits = i >= 0 ? i : i ^ 0x7fffffff;
  float f;
  static_assert(sizeof(f) == sizeof(bits));
  std::memcpy(&f, &bits, sizeof(f));
  return f;
}

}  // namespace fq::cuda
