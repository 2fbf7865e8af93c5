// Refinement passes of the CUDA engine: one thread per vertex or per triangle, each
// calling the host+device math of kernels/refine_math.h exactly as cpu_stages.cpp does.
#include <utility>

#include "kernels/cuda/cuda_check.cuh"
#include "kernels/cuda/launch.cuh"
#include "kernels/cuda/refine_passes.cuh"
#include "kernels/refine_math.h"
#include "kernels/refine_schedule.h"

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

__global__ void free_directions_kernel(uint32_t n, FanView fan, const Vec3* normals, const uint8_t* closed,
                                      FreeDirections* out) {
  const uint32_t v = blockIdx.x * blockDim.x + threadIdx.x;
  if (v < n) out[v] = free_directions(fan, normals, v, closed[v] != 0);
}

__global__ void vertex_update_kernel(uint32_t n, FanView fan, const Vec3* x, const Vec3* normals,
                                     const FreeDirections* dirs, float tangential_step, Vec3* out) {
  const uint32_t v = blockIdx.x * blockDim.x + threadIdx.x;
  if (v < n) out[v] = updated_vertex(fan, x, normals, v, dirs[v], tangential_step);
}

// One warp per block of faces: the lanes' sums added by a shuffle tree, in the order of
// refine_math.h's normal_change_block. Launched with whole warps (kChangeThreads).
__global__ void change_block_kernel(uint32_t blocks, uint32_t m, const uint32_t* tris, const Point4* in,
                                    const Vec3* out, float* sums) {
  const uint32_t block = (blockIdx.x * blockDim.x + threadIdx.x) / kChangeLanes;
  const uint32_t lane = threadIdx.x % kChangeLanes;
  if (block >= blocks) return;  // the same for every lane of a warp
  float sum = normal_change_lane(tris, m, in, out, block, lane);
  for (uint32_t apart = kChangeLanes / 2; apart > 0; apart /= 2) sum = sum + __shfl_down_sync(~0u, sum, apart);
  if (lane == 0) sums[block] = sum;
}

constexpr uint32_t kChangeThreads = 4 * kChangeLanes;

// One thread: the block sums in block order, as the CPU adds them; the guard's strength
// goes to slot `blocks`, the rough-input weight to `blocks + 1`.
__global__ void strength_kernel(uint32_t blocks, uint32_t m, float clean_below, float full_above, float rough_from,
                                float rough_full, float* sums) {
  sums[blocks] = refine_strength(sums, m, clean_below, full_above);
  sums[blocks + 1] = rough_weight(sums, m, rough_from, rough_full);
}

__global__ void input_positions_kernel(uint32_t n, const Point4* in, Vec3* out) {
  const uint32_t v = blockIdx.x * blockDim.x + threadIdx.x;
  if (v < n) out[v] = xyz(in[v]);
}

__global__ void blend_kernel(uint32_t n, const Vec3* fine, const Vec3* rough, float beta, Vec3* out) {
  const uint32_t v = blockIdx.x * blockDim.x + threadIdx.x;
  if (v < n) out[v] = blended_position(fine[v], rough[v], beta);
}

__global__ void guard_kernel(uint32_t n, const Point4* in, const Vec3* x, const float* alpha, Vec3* out) {
  const uint32_t v = blockIdx.x * blockDim.x + threadIdx.x;
  if (v < n) out[v] = *alpha < 1.f ? guarded_position(in[v], x[v], *alpha) : x[v];
}

// One refinement run (fine or rough schedule) on f.moved: every vertex pass reads f.moved
// and writes b.x, then the buffers trade places.
void run_refinement(DeviceFrame& f, RefineBuffers& b, const FanView& fan, const RefineSchedule& r, cudaStream_t s) {
  const uint32_t n = f.n, m = f.m;
  for (int it = 0; it < r.relax_iterations; ++it) {
    relax_kernel<<<blocks_for(n), block_size(), 0, s>>>(n, fan, f.moved.data(), b.closed.data(), r.relax_step,
                                                        r.feature_ratio, b.x.data());
    FQ_CUDA_CHECK_LAUNCH("relax_kernel");
    std::swap(f.moved, b.x);
  }
  Vec3* normals[2] = {b.normals[0].reserve(m), b.normals[1].reserve(m)};
  TriangleGeom* geom = b.geom.reserve(m);
  FreeDirections* dirs = b.dirs.reserve(n);
  for (int round = 0; round < r.rounds; ++round) {
    face_geometry_kernel<<<blocks_for(m), block_size(), 0, s>>>(m, f.tris.data(), f.moved.data(), geom, normals[0]);
    FQ_CUDA_CHECK_LAUNCH("face_geometry_kernel");
    for (int it = 0; it < r.normal_iterations; ++it) {
      normal_filter_kernel<<<blocks_for(m), block_size(), 0, s>>>(m, fan, geom, normals[it & 1], r.gs, r.gr,
                                                                  normals[(it + 1) & 1]);
      FQ_CUDA_CHECK_LAUNCH("normal_filter_kernel");
    }
    const Vec3* filtered = normals[r.normal_iterations & 1];
    free_directions_kernel<<<blocks_for(n), block_size(), 0, s>>>(n, fan, filtered, b.closed.data(), dirs);
    FQ_CUDA_CHECK_LAUNCH("free_directions_kernel");
    for (int it = 0; it < r.vertex_iterations; ++it) {
      vertex_update_kernel<<<blocks_for(n), block_size(), 0, s>>>(n, fan, f.moved.data(), filtered, dirs,
                                                                  r.tangential_step, b.x.data());
      FQ_CUDA_CHECK_LAUNCH("vertex_update_kernel");
      std::swap(f.moved, b.x);
    }
  }
}

}  // namespace

void refine_positions(DeviceFrame& f, RefineBuffers& b, const RefineParams& r, cudaStream_t s) {
  const uint32_t n = f.n, m = f.m;
  const FanView fan{f.tris.data(), f.vf_start.data(), f.vf_faces.data()};
  b.x.reserve(n);
  // The vertex update's free directions read it too.
  closed_fan_kernel<<<blocks_for(n), block_size(), 0, s>>>(n, fan, b.closed.reserve(n));
  FQ_CUDA_CHECK_LAUNCH("closed_fan_kernel");
  run_refinement(f, b, fan, fine_schedule(r), s);
  if (!(r.full_above > 0.f)) return;
  const uint32_t blocks = normal_change_blocks(m);
  float* change = b.change.reserve(blocks + 2);
  change_block_kernel<<<(blocks + kChangeThreads / kChangeLanes - 1) / (kChangeThreads / kChangeLanes),
                        kChangeThreads, 0, s>>>(blocks, m, f.tris.data(), f.points.data(), f.moved.data(), change);
  FQ_CUDA_CHECK_LAUNCH("change_block_kernel");
  const bool rough_on = rough_path_on(r);
  strength_kernel<<<1, 1, 0, s>>>(blocks, m, r.clean_below, r.full_above, rough_on ? r.rough_from : 0.f,
                                  rough_on ? r.rough_full : 0.f, change);
  FQ_CUDA_CHECK_LAUNCH("strength_kernel");
  float beta = 0.f;
  if (rough_on) {  // the host decides whether the rough-input run goes at all
    float* h = b.h_rough.reserve(1);
    FQ_CUDA_CHECK(cudaMemcpyAsync(h, change + blocks + 1, sizeof(float), cudaMemcpyDeviceToHost, s));
    FQ_CUDA_CHECK(cudaStreamSynchronize(s));
    beta = *h;
  }
  if (beta > 0.f) {  // rough_from >= full_above: the guard's strength is 1 here
    Vec3* fine = b.fine.reserve(n);
    FQ_CUDA_CHECK(cudaMemcpyAsync(fine, f.moved.data(), n * sizeof(Vec3), cudaMemcpyDeviceToDevice, s));
    input_positions_kernel<<<blocks_for(n), block_size(), 0, s>>>(n, f.points.data(), f.moved.data());
    FQ_CUDA_CHECK_LAUNCH("input_positions_kernel");
    run_refinement(f, b, fan, rough_schedule(r), s);
    blend_kernel<<<blocks_for(n), block_size(), 0, s>>>(n, fine, f.moved.data(), beta, b.x.data());
    FQ_CUDA_CHECK_LAUNCH("blend_kernel");
    std::swap(f.moved, b.x);
    return;
  }
  guard_kernel<<<blocks_for(n), block_size(), 0, s>>>(n, f.points.data(), f.moved.data(), change + blocks, b.x.data());
  FQ_CUDA_CHECK_LAUNCH("guard_kernel");
  std::swap(f.moved, b.x);
}

}  // namespace fq::cuda
