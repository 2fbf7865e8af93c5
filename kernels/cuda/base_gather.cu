// Base quadrics by gathering: a vertex -> triangle table built by counting sort (integer
// atomics + CUB scan), each vertex's triangles put back in increasing order by a CUB
// segmented sort, then one thread per vertex sums its triangles in that order -- the CPU
// engine's (cpu_stages.cpp base_quadrics), so the result is deterministic. (Float4 atomics
// per triangle were slower and L2-bound: docs/BENCHMARKS.md.) The segmented sort handles
// any valence: a fan of 1e5 triangles on one vertex is sorted by a whole block, where a
// per-thread insertion sort took O(valence^2).
#include <algorithm>
#include <cub/device/device_scan.cuh>
#include <cub/device/device_segmented_sort.cuh>
#include <utility>

#include "kernels/cuda/cuda_check.cuh"
#include "kernels/cuda/launch.cuh"
#include "kernels/cuda/passes.cuh"

namespace fq::cuda {

namespace {

__global__ void triangle_geometry(uint32_t m, const uint32_t* tris, const Point4* points,
                                  TriangleGeom* geom) {
  const uint64_t t = item_index();
  if (t >= m) return;
  const uint32_t* tri = tris + 3 * size_t(t);
  geom[t] = triangle_geom(xyz(points[tri[0]]), xyz(points[tri[1]]), xyz(points[tri[2]]));
}

__global__ void count_corners(uint64_t corners, const uint32_t* tris, uint32_t* count, uint32_t* slot) {
  const uint64_t c = item_index();
  if (c < corners) slot[c] = atomicAdd(&count[tris[c]], 1u);
}

__global__ void scatter_corners(uint64_t corners, const uint32_t* tris, const uint32_t* start,
                                const uint32_t* slot, uint32_t* faces) {
  const uint64_t c = item_index();
  if (c < corners) faces[start[tris[c]] + slot[c]] = static_cast<uint32_t>(c / 3);
}

// Per vertex: its triangles, in increasing order, summed exactly as the CPU does.
__global__ void gather_base(uint32_t n, const uint32_t* start, const uint32_t* faces,
                            const TriangleGeom* geom, Point4* points, Quadric* base, PackedQuadric* base_p,
                            Vec3* vnormal) {
  const uint64_t v = item_index();
  if (v >= n) return;
  const uint32_t b = start[v], e = start[v + 1];
  const Vec3 x = xyz(points[v]);
  VertexAccum acc = zero_vertex_accum();
  for (uint32_t k = b; k < e; ++k) add_triangle(acc, geom[faces[k]], x);
  base[v] = base_quadric(acc);
  base_p[v] = pack(base[v]);
  points[v].w = acc.area;
  vnormal[v] = acc.normal;
}

}  // namespace

void base_quadrics(DeviceFrame& f, cudaStream_t s) {
  const uint32_t n = f.n, m = f.m;
  const uint64_t corners = 3 * uint64_t(m);
  uint32_t* count = f.vf_count.reserve(n + 1);
  uint32_t* start = f.vf_start.reserve(n + 1);
  // The arrival slots are dead once the corners are scattered: their buffer is the sort's
  // second half, and the sorted faces end up in whichever `faces` names.
  cub::DoubleBuffer<uint32_t> faces(f.vf_faces.reserve(corners), f.vf_slot.reserve(corners));
  size_t scan_bytes = 0, sort_bytes = 0;
  FQ_CUDA_CHECK(cub::DeviceScan::ExclusiveSum(nullptr, scan_bytes, count, start, int(n + 1), s));
  FQ_CUDA_CHECK(cub::DeviceSegmentedSort::SortKeys(nullptr, sort_bytes, faces, int(corners), int(n), start,
                                                   start + 1, s));
  const size_t temp_bytes = std::max(scan_bytes, sort_bytes);
  unsigned char* temp = f.temp.reserve(temp_bytes);

  FQ_LAUNCH(triangle_geometry, m, s, m, f.tris.data(), f.points.data(), f.tri_geom.reserve(m));
  FQ_CUDA_CHECK(cudaMemsetAsync(count, 0, (n + 1) * sizeof(uint32_t), s));
  FQ_LAUNCH(count_corners, corners, s, corners, f.tris.data(), count, f.vf_slot.reserve(corners));
  size_t bytes = temp_bytes;
  FQ_CUDA_CHECK(cub::DeviceScan::ExclusiveSum(temp, bytes, count, start, int(n + 1), s));
  FQ_LAUNCH(scatter_corners, corners, s, corners, f.tris.data(), start, f.vf_slot.data(), f.vf_faces.data());
  bytes = temp_bytes;
  FQ_CUDA_CHECK(
      cub::DeviceSegmentedSort::SortKeys(temp, bytes, faces, int(corners), int(n), start, start + 1, s));
  FQ_LAUNCH(gather_base, n, s, n, start, faces.Current(), f.tri_geom.data(), f.points.data(),
            f.base.reserve(n), f.base_p.reserve(n), f.vnormal.reserve(n));
  // Later passes (the "qf+" refinement) read the sorted table as vf_faces.
  if (faces.Current() != f.vf_faces.data()) std::swap(f.vf_faces, f.vf_slot);
}

}  // namespace fq::cuda
