// Base quadrics by gathering instead of float atomics: a vertex -> triangle table built by
// counting sort (integer atomics + CUB scan), then one thread per vertex sums its
// triangles in increasing triangle order -- the CPU engine's order (cpu_stages.cpp
// base_quadrics), so the result is deterministic. Chosen over the float4-atomic version
// when it measures faster (see docs/BENCHMARKS.md).
#include <algorithm>
#include <cub/device/device_scan.cuh>

#include "kernels/cuda/cuda_check.cuh"
#include "kernels/cuda/launch.cuh"
#include "kernels/cuda/passes.cuh"

namespace fq::cuda {

namespace {

__global__ void triangle_geometry(uint32_t m, const uint32_t* tris, const Point4* points,
                                  TriangleGeom* geom) {
  const uint32_t t = blockIdx.x * blockDim.x + threadIdx.x;
  if (t >= m) return;
  const uint32_t* tri = tris + 3 * size_t(t);
  geom[t] = triangle_geom(xyz(points[tri[0]]), xyz(points[tri[1]]), xyz(points[tri[2]]));
}

__global__ void count_corners(uint64_t corners, const uint32_t* tris, uint32_t* count, uint32_t* slot) {
  const uint64_t c = uint64_t(blockIdx.x) * blockDim.x + threadIdx.x;
  if (c < corners) slot[c] = atomicAdd(&count[tris[c]], 1u);
}

__global__ void scatter_corners(uint64_t corners, const uint32_t* tris, const uint32_t* start,
                                const uint32_t* slot, uint32_t* faces) {
  const uint64_t c = uint64_t(blockIdx.x) * blockDim.x + threadIdx.x;
  if (c < corners) faces[start[tris[c]] + slot[c]] = static_cast<uint32_t>(c / 3);
}

// Per vertex: its triangles put in increasing order (atomics gave any order), then
// summed exactly as the CPU does.
__global__ void gather_base(uint32_t n, const uint32_t* start, uint32_t* faces, const TriangleGeom* geom,
                            Point4* points, Quadric* base, PackedQuadric* base_p, Vec3* vnormal) {
  const uint32_t v = blockIdx.x * blockDim.x + threadIdx.x;
  if (v >= n) return;
  const uint32_t b = start[v], e = start[v + 1];
  for (uint32_t k = b + 1; k < e; ++k) {
    const uint32_t t = faces[k];
    uint32_t h = k;
    for (; h > b && faces[h - 1] > t; --h) faces[h] = faces[h - 1];
    faces[h] = t;
  }
  const Vec3 x = xyz(points[v]);
  VertexAccum acc = zero_vertex_accum();
  for (uint32_t k = b; k < e; ++k) add_triangle(acc, geom[faces[k]], x);
  base[v] = base_quadric(acc);
  base_p[v] = pack(base[v]);
  points[v].w = acc.area;
  vnormal[v] = acc.normal;
}

}  // namespace

void base_quadrics_gather(DeviceFrame& f, cudaStream_t s) {
  const uint32_t n = f.n, m = f.m;
  const uint64_t corners = 3 * uint64_t(m);
  uint32_t* count = f.vf_count.reserve(n + 1);
  uint32_t* start = f.vf_start.reserve(n + 1);
  size_t bytes = 0;
  FQ_CUDA_CHECK(cub::DeviceScan::ExclusiveSum(nullptr, bytes, count, start, int(n + 1), s));
  unsigned char* temp = f.temp.reserve(bytes);

  triangle_geometry<<<blocks_for(m), block_size(), 0, s>>>(m, f.tris.data(), f.points.data(),
                                                           f.tri_geom.reserve(m));
  FQ_CUDA_CHECK_LAUNCH("triangle_geometry");
  FQ_CUDA_CHECK(cudaMemsetAsync(count, 0, (n + 1) * sizeof(uint32_t), s));
  count_corners<<<blocks_for(corners), block_size(), 0, s>>>(corners, f.tris.data(), count,
                                                             f.vf_slot.reserve(corners));
  FQ_CUDA_CHECK_LAUNCH("count_corners");
  FQ_CUDA_CHECK(cub::DeviceScan::ExclusiveSum(temp, bytes, count, start, int(n + 1), s));
  scatter_corners<<<blocks_for(corners), block_size(), 0, s>>>(corners, f.tris.data(), start,
                                                               f.vf_slot.data(), f.vf_faces.reserve(corners));
  FQ_CUDA_CHECK_LAUNCH("scatter_corners");
  gather_base<<<blocks_for(n), block_size(), 0, s>>>(n, start, f.vf_faces.data(), f.tri_geom.data(),
                                                     f.points.data(), f.base.reserve(n), f.base_p.reserve(n),
                                                     f.vnormal.reserve(n));
  FQ_CUDA_CHECK_LAUNCH("gather_base");
}

}  // namespace fq::cuda
