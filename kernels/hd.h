// Host+device marker for math written once and called by the CPU and the CUDA engine.
// Empty for a plain C++ compiler; nvcc sees __host__ __device__.
#pragma once

#if defined(__CUDACC__)
#define FQ_HD __host__ __device__ __forceinline__
#else
#define FQ_HD inline
#endif

// Unroll hint for fixed-trip loops (register arrays stay in registers on the GPU).
#if defined(__CUDACC__)
#define FQ_UNROLL _Pragma("unroll")
#else
#define FQ_UNROLL
#endif
