// Built with -fmad=false (kernels/CMakeLists.txt): no multiply-add is fused, so every edge
// length and both maps of frame_prep.h give the host's floats bit for bit. Only the order
// of the edge-length sum differs from the host's, which can move the mean edge in its last
// bits (see docs/BENCHMARKS.md, Correctness).
#include <cfloat>
#include <climits>
#include <cmath>
#include <cub/block/block_reduce.cuh>

#include "kernels/cuda/cuda_check.cuh"
#include "kernels/cuda/frame_checks.cuh"
#include "kernels/cuda/launch.cuh"
#include "kernels/cuda/ordered_float.cuh"

namespace fq::cuda {

namespace {

// The reductions run on a fixed grid, so the partial sums, and the order in which they are
// combined, are the same on every run: the mean edge is reproducible.
constexpr unsigned kThreads = tuning::kReduceBlock;
constexpr unsigned kBlocks = tuning::kReduceGrid;
using ULL = unsigned long long;

struct MinOp {
  __device__ float operator()(float a, float b) const { return fminf(a, b); }
};
struct MaxOp {
  __device__ float operator()(float a, float b) const { return fmaxf(a, b); }
};

__global__ void reset_stats(FrameStats* st) {
  for (int k = 0; k < 3; ++k) {
    st->lo[k] = INT_MAX;
    st->hi[k] = INT_MIN;
  }
  st->bad_coordinate = ULL(kNone);
  st->bad_index = ULL(kNone);
  st->edge_sum = 0.0;
}

__global__ void __launch_bounds__(kThreads) vertex_checks(uint32_t n, const float* coords, FrameStats* st) {
  using Reduce = cub::BlockReduce<float, kThreads>;
  __shared__ typename Reduce::TempStorage temp;
  float lo[3] = {FLT_MAX, FLT_MAX, FLT_MAX}, hi[3] = {-FLT_MAX, -FLT_MAX, -FLT_MAX};
  for (uint64_t i = uint64_t(blockIdx.x) * blockDim.x + threadIdx.x; i < n;
       i += uint64_t(gridDim.x) * blockDim.x) {
#pragma unroll
    for (int k = 0; k < 3; ++k) {
      const float c = coords[3 * i + k];
      if (!isfinite(c)) atomicMin(&st->bad_coordinate, ULL(3 * i + k));
      lo[k] = fminf(lo[k], c);
      hi[k] = fmaxf(hi[k], c);
    }
  }
#pragma unroll
  for (int k = 0; k < 3; ++k) {
    const float l = Reduce(temp).Reduce(lo[k], MinOp{});
    __syncthreads();
    const float h = Reduce(temp).Reduce(hi[k], MaxOp{});
    __syncthreads();
    if (threadIdx.x == 0) {
      atomicMin(&st->lo[k], ordered_int(l));
      atomicMax(&st->hi[k], ordered_int(h));
    }
  }
}

// Per block: the edge lengths of its triangles (frame_prep.cpp mean_edge_length's terms)
// summed in double; triangles with an index out of range are reported and skipped.
__global__ void __launch_bounds__(kThreads)
    triangle_checks(uint32_t m, uint32_t n, const uint32_t* tris, const float* coords, FrameStats* st,
                    double* partial) {
  using Reduce = cub::BlockReduce<double, kThreads>;
  __shared__ typename Reduce::TempStorage temp;
  double sum = 0.0;
  for (uint64_t t = uint64_t(blockIdx.x) * blockDim.x + threadIdx.x; t < m;
       t += uint64_t(gridDim.x) * blockDim.x) {
    const uint32_t v[3] = {tris[3 * t], tris[3 * t + 1], tris[3 * t + 2]};
    int bad = -1;
#pragma unroll
    for (int k = 2; k >= 0; --k) bad = v[k] >= n ? k : bad;
    if (bad >= 0) {
      atomicMin(&st->bad_index, ULL(3 * t + bad));
      continue;
    }
#pragma unroll
    for (int e = 0; e < 3; ++e) {
      const float* a = coords + 3 * size_t(v[e]);
      const float* b = coords + 3 * size_t(v[(e + 1) % 3]);
      const double dx = double(a[0]) - b[0], dy = double(a[1]) - b[1], dz = double(a[2]) - b[2];
      sum += sqrt(dx * dx + dy * dy + dz * dz);
    }
  }
  const double block_sum = Reduce(temp).Sum(sum);
  if (threadIdx.x == 0) partial[blockIdx.x] = block_sum;
}

__global__ void __launch_bounds__(kThreads) sum_partials(const double* partial, FrameStats* st) {
  using Reduce = cub::BlockReduce<double, kThreads>;
  __shared__ typename Reduce::TempStorage temp;
  double sum = 0.0;
  for (unsigned k = threadIdx.x; k < kBlocks; k += kThreads) sum += partial[k];
  const double total = Reduce(temp).Sum(sum);
  if (threadIdx.x == 0) st->edge_sum = total;
}

__global__ void normalize_kernel(uint32_t n, const float* coords, Normalization norm, Point4* out) {
  const uint64_t i = item_index();
  if (i >= n) return;
  const Vec3 p = norm.to_normalized(coords + 3 * size_t(i));
  out[i] = {p.x, p.y, p.z, 0.f};
}

__global__ void to_input_kernel(uint32_t n, const uint32_t* rank, const Vec3* moved, Normalization norm,
                                float* out) {
  const uint64_t i = item_index();
  if (i < n) norm.to_input(moved[rank[i]], out + 3 * size_t(i));
}

}  // namespace

void reduce_frame(DeviceFrame& f, cudaStream_t s) {
  FrameStats* st = f.stats.reserve(1);
  double* partial = f.edge_partials.reserve(kBlocks);
  FQ_LAUNCH(reset_stats, launch_shape(1, tuning::kSingleThread), s, st);
  FQ_LAUNCH(vertex_checks, launch_shape(kBlocks, kThreads), s, f.n, f.in_coords.data(), st);
  FQ_LAUNCH(triangle_checks, launch_shape(kBlocks, kThreads), s, f.m, f.n, f.in_tris.data(),
            f.in_coords.data(), st, partial);
  FQ_LAUNCH(sum_partials, launch_shape(1, kThreads), s, partial, st);
  FQ_CUDA_CHECK(cudaMemcpyAsync(f.h_stats.reserve(1), st, sizeof(FrameStats), cudaMemcpyDeviceToHost, s));
}

FrameSummary read_summary(const DeviceFrame& f) {
  const FrameStats& st = *f.h_stats.data();
  FrameSummary out;
  out.bad_coordinate = st.bad_coordinate;
  out.bad_index = st.bad_index;
  for (int k = 0; k < 3; ++k) {
    out.lo[k] = from_ordered_int(st.lo[k]);
    out.hi[k] = from_ordered_int(st.hi[k]);
  }
  out.mean_edge = st.edge_sum / (3.0 * f.m);
  return out;
}

void normalize_points(DeviceFrame& f, const Normalization& norm, cudaStream_t s) {
  FQ_LAUNCH(normalize_kernel, f.n, s, f.n, f.in_coords.data(), norm, f.in_points.reserve(f.n));
}

void positions_to_input(DeviceFrame& f, const Normalization& norm, cudaStream_t s) {
  FQ_LAUNCH(to_input_kernel, f.n, s, f.n, f.grid.rank.data(), f.moved.data(), norm,
            f.out_coords.reserve(3 * size_t(f.n)));
}

}  // namespace fq::cuda
