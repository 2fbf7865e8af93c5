// The threads that decode one chunk together (chunk_decode.cu): one thread, a warp, or a
// block of T threads. The kernel is written once over these few steps; a warp's go through
// shuffles and votes, a block's through shared memory and __syncthreads.
#pragma once

#include <cstdint>
#include <cstring>

namespace fq::cuda {

/// What a block's team keeps in shared memory for its steps.
struct TeamScratch {
  uint32_t words[24];           ///< share(): the first lane's value, up to 96 bytes
  unsigned long long sums[32];  ///< scan(): each warp's total
};

/// T threads on one chunk: 1, 32 (a warp) or a multiple of 32 up to 1024 (a block).
template <int T>
struct Team {
  static_assert(T == 1 || (T % 32 == 0 && T <= 1024), "one thread, a warp or a block of warps");
  unsigned lane;                   ///< threadIdx.x within the team
  TeamScratch* scratch = nullptr;  ///< a block's shared scratch (T > 32)

  __device__ bool is_first() const { return lane == 0; }

  /// Every lane's memory writes so far, visible to every lane.
  __device__ void sync() const {
    if constexpr (T == 32) __syncwarp();
    if constexpr (T > 32) __syncthreads();
  }

  /// Whether p holds on some lane (every lane gets the answer).
  __device__ bool any(bool p) const {
    if constexpr (T == 1) {
      return p;
    } else if constexpr (T == 32) {
      return __any_sync(0xffffffffu, p);
    } else {
      return __syncthreads_or(p) != 0;
    }
  }

  /// The first lane's `v` to every lane (a value: memory the first lane wrote needs sync() too).
  template <class V>
  __device__ void share(V& v) const {
    static_assert(sizeof(V) % 4 == 0 && sizeof(V) <= sizeof(TeamScratch::words), "shared 4 bytes at a time");
    if constexpr (T == 32) {
      uint32_t w[sizeof(V) / 4];
      memcpy(w, &v, sizeof(V));
#pragma unroll
      for (unsigned k = 0; k < sizeof(V) / 4; ++k) w[k] = __shfl_sync(0xffffffffu, w[k], 0);
      memcpy(&v, w, sizeof(V));
    }
    if constexpr (T > 32) {
      if (is_first()) memcpy(scratch->words, &v, sizeof(V));
      __syncthreads();
      if (!is_first()) memcpy(&v, scratch->words, sizeof(V));
      __syncthreads();
    }
  }

  /// The inclusive scan of v over the lanes in lane order by `op` (associative, 0 its
  /// identity); `total` gets the last lane's, on every lane. V is an unsigned integer.
  template <class V, class Op>
  __device__ V scan(V v, Op op, V& total) const {
    if constexpr (T == 1) {
      total = v;
      return v;
    } else {
      const unsigned l = lane & 31;
#pragma unroll
      for (unsigned o = 1; o < 32; o <<= 1) {
        const V up = __shfl_up_sync(0xffffffffu, v, o);
        if (l >= o) v = op(up, v);
      }
      if constexpr (T == 32) {
        total = __shfl_sync(0xffffffffu, v, 31);
        return v;
      } else {
        if (l == 31) scratch->sums[lane >> 5] = v;
        __syncthreads();
        if (lane < 32) {
          V w = lane < T / 32 ? V(scratch->sums[lane]) : V(0);
#pragma unroll
          for (unsigned o = 1; o < 32; o <<= 1) {
            const V up = __shfl_up_sync(0xffffffffu, w, o);
            if (lane >= o) w = op(up, w);
          }
          scratch->sums[lane] = w;
        }
        __syncthreads();
        if (lane >= 32) v = op(V(scratch->sums[(lane >> 5) - 1]), v);
        total = V(scratch->sums[T / 32 - 1]);
        __syncthreads();
        return v;
      }
    }
  }
};

}  // namespace fq::cuda
