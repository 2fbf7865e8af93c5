// Refinement passes of the CUDA engine: one thread per vertex or per triangle, each
// calling the host+device math of kernels/refine_math.h exactly as cpu_stages.cpp does.
#include <utility>

#include "kernels/cuda/cuda_check.cuh"
#include "kernels/cuda/launch.cuh"
#include "kernels/cuda/refine_passes.cuh"
#include "kernels/refine_math.h"

namespace fq::cuda {

namespace {

__global__ void closed_fan_kernel(uint32_t n, FanView fan, uint8_t* closed) {
  const uint32_t v = blockIdx.x * blockDim.x + threadIdx.x;
  if (v < n) closed[v] = closed_fan(fan, v) ? 1 : 0;
}

__global__ void relax_kernel(uint32_t n, FanView fan, const Vec3* x, const uint8_t* closed, float step, float ratio,
                             Vec3* out) {
  const uint32_t v = blockIdx.x * blockDim.x + threadIdx.x;
  if (v < n) out[v] = relaxed_position(fan, x, v, closed[v] != 0, step, ratio);
}

__global__ void face_geometry_kernel(uint32_t m, const uint32_t* tris, const Vec3* x, TriangleGeom* geom,
                                     Vec3* normals) {
  const uint32_t t = blockIdx.x * blockDim.x + threadIdx.x;
  if (t >= m) return;
  const uint32_t* tri = tris + 3 * size_t(t);
  geom[t] = triangle_geom(x[tri[0]], x[tri[1]], x[tri[2]]);
  normals[t] = geom[t].normal;
}

__global__ void normal_filter_kernel(uint32_t m, FanView fan, const TriangleGeom* geom, const Vec3* in,
                                     Gaussian gs, Gaussian gr, Vec3* out) {
  const uint32_t t = blockIdx.x * blockDim.x + threadIdx.x;
  if (t < m) out[t] = filtered_face_normal(fan, geom, in, t, gs, gr);
}

__global__ void vertex_update_kernel(uint32_t n, FanView fan, const Vec3* x, const Vec3* normals, Vec3* out) {
  const uint32_t v = blockIdx.x * blockDim.x + threadIdx.x;
  if (v < n) out[v] = normal_driven_position(fan, x, normals, v);
}

__global__ void normal_change_kernel(uint32_t blocks, uint32_t m, const uint32_t* tris, const Point4* in,
                                     const Vec3* out, float* sums) {
  const uint32_t b = blockIdx.x * blockDim.x + threadIdx.x;
  if (b < blocks) sums[b] = normal_change_block(tris, m, in, out, b);
}

// One thread: the block sums in block order, as the CPU adds them.
__global__ void strength_kernel(uint32_t blocks, uint32_t m, float clean_below, float full_above, float* sums) {
  sums[blocks] = refine_strength(sums, m, clean_below, full_above);
}

__global__ void guard_kernel(uint32_t n, const Point4* in, const Vec3* x, const float* alpha, Vec3* out) {
  const uint32_t v = blockIdx.x * blockDim.x + threadIdx.x;
  if (v < n) out[v] = *alpha < 1.f ? guarded_position(in[v], x[v], *alpha) : x[v];
}

}  // namespace

void refine_positions(DeviceFrame& f, RefineBuffers& b, const RefineParams& r, cudaStream_t s) {
  const uint32_t n = f.n, m = f.m;
  const FanView fan{f.tris.data(), f.vf_start.data(), f.vf_faces.data()};
  b.x.reserve(n);
  if (r.relax_iterations > 0) {
    closed_fan_kernel<<<blocks_for(n), block_size(), 0, s>>>(n, fan, b.closed.reserve(n));
    FQ_CUDA_CHECK_LAUNCH("closed_fan_kernel");
  }
  // Every vertex pass reads f.moved and writes b.x, then the buffers trade places.
  for (int it = 0; it < r.relax_iterations; ++it) {
    relax_kernel<<<blocks_for(n), block_size(), 0, s>>>(n, fan, f.moved.data(), b.closed.data(), r.relax_step,
                                                        r.feature_ratio, b.x.data());
    FQ_CUDA_CHECK_LAUNCH("relax_kernel");
    std::swap(f.moved, b.x);
  }
  Vec3* normals[2] = {b.normals[0].reserve(m), b.normals[1].reserve(m)};
  face_geometry_kernel<<<blocks_for(m), block_size(), 0, s>>>(m, f.tris.data(), f.moved.data(), b.geom.reserve(m),
                                                              normals[0]);
  FQ_CUDA_CHECK_LAUNCH("face_geometry_kernel");
  const Gaussian gs = Gaussian::with_sigma(r.normal_sigma_s), gr = Gaussian::with_sigma(r.normal_sigma_r);
  for (int it = 0; it < r.normal_iterations; ++it) {
    normal_filter_kernel<<<blocks_for(m), block_size(), 0, s>>>(m, fan, b.geom.data(), normals[it & 1], gs, gr,
                                                                normals[(it + 1) & 1]);
    FQ_CUDA_CHECK_LAUNCH("normal_filter_kernel");
  }
  const Vec3* filtered = normals[r.normal_iterations & 1];
  for (int it = 0; it < r.vertex_iterations; ++it) {
    vertex_update_kernel<<<blocks_for(n), block_size(), 0, s>>>(n, fan, f.moved.data(), filtered, b.x.data());
    FQ_CUDA_CHECK_LAUNCH("vertex_update_kernel");
    std::swap(f.moved, b.x);
  }
  if (!(r.full_above > 0.f)) return;
  const uint32_t blocks = normal_change_blocks(m);
  float* change = b.change.reserve(blocks + 1);
  normal_change_kernel<<<blocks_for(blocks), block_size(), 0, s>>>(blocks, m, f.tris.data(), f.points.data(),
                                                                   f.moved.data(), change);
  FQ_CUDA_CHECK_LAUNCH("normal_change_kernel");
  strength_kernel<<<1, 1, 0, s>>>(blocks, m, r.clean_below, r.full_above, change);
  FQ_CUDA_CHECK_LAUNCH("strength_kernel");
  guard_kernel<<<blocks_for(n), block_size(), 0, s>>>(n, f.points.data(), f.moved.data(), change + blocks, b.x.data());
  FQ_CUDA_CHECK_LAUNCH("guard_kernel");
  std::swap(f.moved, b.x);
}

}  // namespace fq::cuda
