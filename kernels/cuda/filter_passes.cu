// Filter passes of the CUDA engine: one thread per vertex (grid order) or per triangle,
// each calling the same host+device math as the CPU engine (kernels/*_math.h).
#include "kernels/cuda/cuda_check.cuh"
#include "kernels/filter_math.h"
#include "kernels/gaussian.h"
#include "kernels/cuda/launch.cuh"
#include "kernels/cuda/passes.cuh"

namespace fq::cuda {

namespace {

__global__ void renumber_triangles(uint64_t count, const uint32_t* in, const uint32_t* rank, uint32_t* out) {
  const uint64_t t = uint64_t(blockIdx.x) * blockDim.x + threadIdx.x;
  if (t < count) out[t] = rank[in[t]];
}

__device__ void add4(float4* a, float4 v) {
#if defined(__CUDA_ARCH__) && __CUDA_ARCH__ >= 900
  atomicAdd(a, v);  // one 16-byte atomic (Hopper, global memory)
#else
  atomicAdd(&a->x, v.x);
  atomicAdd(&a->y, v.y);
  atomicAdd(&a->z, v.z);
  atomicAdd(&a->w, v.w);
#endif
}

__device__ void add2(float4* a, float x, float y) {
#if defined(__CUDA_ARCH__) && __CUDA_ARCH__ >= 900
  atomicAdd(reinterpret_cast<float2*>(a), float2{x, y});
#else
  atomicAdd(&a->x, x);
  atomicAdd(&a->y, y);
#endif
}

// Each corner's share of its triangle's plane quadric, added into the corner's sums.
__global__ void triangle_quadrics(uint32_t m, const uint32_t* tris, const Point4* points, TriangleGeom* geom,
                                  float4* accum) {
  const uint32_t t = blockIdx.x * blockDim.x + threadIdx.x;
  if (t >= m) return;
  const uint32_t v[3] = {tris[3 * size_t(t)], tris[3 * size_t(t) + 1], tris[3 * size_t(t) + 2]};
  const Vec3 p[3] = {xyz(points[v[0]]), xyz(points[v[1]]), xyz(points[v[2]])};
  const TriangleGeom g = triangle_geom(p[0], p[1], p[2]);
  geom[t] = g;
#pragma unroll
  for (int k = 0; k < 3; ++k) {
    VertexAccum acc = zero_vertex_accum();
    add_triangle(acc, g, p[k]);
    if (!(acc.area > 0.f)) continue;
    float4* a = accum + 4 * size_t(v[k]);
    const Quadric& q = acc.q;
    add4(a, {q.a00, q.a01, q.a02, q.a11});
    add4(a + 1, {q.a12, q.a22, q.b0, q.b1});
    add4(a + 2, {q.b2, q.c, acc.area, acc.normal.x});
    add2(a + 3, acc.normal.y, acc.normal.z);
  }
}

__global__ void finish_base_quadrics(uint32_t n, const float4* accum, Point4* points, Quadric* base,
                                     PackedQuadric* base_p, Vec3* vnormal) {
  const uint32_t v = blockIdx.x * blockDim.x + threadIdx.x;
  if (v >= n) return;
  const float4 a0 = accum[4 * size_t(v)], a1 = accum[4 * size_t(v) + 1];
  const float4 a2 = accum[4 * size_t(v) + 2], a3 = accum[4 * size_t(v) + 3];
  VertexAccum acc;
  acc.q = {a0.x, a0.y, a0.z, a0.w, a1.x, a1.y, a1.z, a1.w, a2.x, a2.y};
  acc.area = a2.z;
  acc.normal = {a2.w, a3.x, a3.y};
  base[v] = base_quadric(acc);
  base_p[v] = pack(base[v]);
  points[v].w = acc.area;
  vnormal[v] = acc.normal;
}

__global__ void neighbourhood_kernel(GridView g, const Quadric* base, Gaussian gb, float radius,
                                     Quadric* out) {
  const uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < g.count) out[i] = neighbourhood_quadric(g, base, i, gb, radius);
}

__global__ void diffusion_kernel(GridView g, const Quadric* nbhd, Gaussian gs, Gaussian gr, float radius,
                                 Quadric* out) {
  const uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < g.count) out[i] = bilateral_quadric(g, nbhd, i, gs, gr, radius);
}

__global__ void update_kernel(GridView g, const Quadric* bl, const Vec3* vnormal, bool constrained,
                              Gaussian gn, float radius_n, float tikhonov, Vec3* moved) {
  const uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= g.count) return;
  const Vec3 n = constrained ? smoothed_normal(g, vnormal, i, gn, radius_n) : Vec3{0.f, 0.f, 0.f};
  moved[i] = updated_position(xyz(g.points[i]), bl[i], constrained, n, tikhonov);
}

__global__ void gather_kernel(uint32_t n, const uint32_t* rank, const Vec3* moved, Vec3* out) {
  const uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n) out[i] = moved[rank[i]];
}

}  // namespace

void sort_into_grid(DeviceFrame& f, const GridLayout& layout, cudaStream_t s) {
  build_device_grid(layout, f.in_points.data(), f.n, f.grid, f.points.reserve(f.n), s);
  const uint64_t idx = 3 * uint64_t(f.m);
  renumber_triangles<<<blocks_for(idx), block_size(), 0, s>>>(idx, f.in_tris.data(), f.grid.rank.data(),
                                                              f.tris.reserve(idx));
  FQ_CUDA_CHECK_LAUNCH("renumber_triangles");
}

void base_quadrics(DeviceFrame& f, cudaStream_t s) {
  float4* accum = f.accum.reserve(4 * size_t(f.n));
  FQ_CUDA_CHECK(cudaMemsetAsync(accum, 0, 4 * size_t(f.n) * sizeof(float4), s));
  triangle_quadrics<<<blocks_for(f.m), block_size(), 0, s>>>(f.m, f.tris.data(), f.points.data(),
                                                             f.tri_geom.reserve(f.m), accum);
  FQ_CUDA_CHECK_LAUNCH("triangle_quadrics");
  finish_base_quadrics<<<blocks_for(f.n), block_size(), 0, s>>>(
      f.n, accum, f.points.data(), f.base.reserve(f.n), f.base_p.reserve(f.n), f.vnormal.reserve(f.n));
  FQ_CUDA_CHECK_LAUNCH("finish_base_quadrics");
}

void neighbourhood_quadrics(DeviceFrame& f, float sigma_b, cudaStream_t s) {
  const GridView g = f.grid.view(f.points.data());
  neighbourhood_kernel<<<blocks_for(f.n), block_size(), 0, s>>>(
      g, f.base.data(), Gaussian::with_sigma(sigma_b), 2.f * sigma_b, f.nbhd.reserve(f.n));
  FQ_CUDA_CHECK_LAUNCH("neighbourhood_kernel");
}

void diffuse_quadrics(DeviceFrame& f, const FilterParams& p, cudaStream_t s) {
  const GridView g = f.grid.view(f.points.data());
  diffusion_kernel<<<blocks_for(f.n), block_size(), 0, s>>>(g, f.nbhd.data(), Gaussian::with_sigma(p.sigma_s),
                                                            Gaussian::with_sigma(p.sigma_r), 2.f * p.sigma_s,
                                                            f.bl.reserve(f.n));
  FQ_CUDA_CHECK_LAUNCH("diffusion_kernel");
}

void update_positions(DeviceFrame& f, const FilterParams& p, cudaStream_t s) {
  const GridView g = f.grid.view(f.points.data());
  const float sn = p.effective_sigma_n();
  update_kernel<<<blocks_for(f.n), block_size(), 0, s>>>(g, f.bl.data(), f.vnormal.data(), p.constrained,
                                                         Gaussian::with_sigma(sn), 2.f * sn, p.tikhonov,
                                                         f.moved.reserve(f.n));
  FQ_CUDA_CHECK_LAUNCH("update_kernel");
}

void gather_moved(DeviceFrame& f, cudaStream_t s) {
  gather_kernel<<<blocks_for(f.n), block_size(), 0, s>>>(f.n, f.grid.rank.data(), f.moved.data(),
                                                         f.moved_in_order.reserve(f.n));
  FQ_CUDA_CHECK_LAUNCH("gather_kernel");
}

}  // namespace fq::cuda
