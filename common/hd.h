// Host+device marker for code written once and called on the CPU and on the GPU: the engines'
// math (kernels/) and the frame codec's Draco decoding (wire/). Empty for a plain C++
// compiler; nvcc sees __host__ __device__.
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
