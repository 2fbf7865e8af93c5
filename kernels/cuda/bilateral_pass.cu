// The bilateral baseline (Jones et al. 2003) on the device: a second grid over triangle
// centroids, mollified face normals, then one thread per vertex. Same math headers as the
// CPU engine (bilateral_math.h).
#include <climits>

#include "kernels/bilateral_math.h"
#include "kernels/cuda/cuda_check.cuh"
#include "kernels/cuda/launch.cuh"
#include "kernels/cuda/ordered_float.cuh"
#include "kernels/cuda/passes.cuh"
#include "kernels/gaussian.h"

namespace fq::cuda {

namespace {

__global__ void reset_bounds(int* b) {
  if (threadIdx.x < 3)
    b[threadIdx.x] = INT_MAX;
  else if (threadIdx.x < 6)
    b[threadIdx.x] = INT_MIN;
}

__global__ void centroid_points(uint32_t m, const TriangleGeom* geom, Point4* out, int* bounds) {
  const uint64_t t = item_index();
  if (t >= m) return;
  const TriangleGeom g = geom[t];
  out[t] = {g.centroid.x, g.centroid.y, g.centroid.z, g.area};
  const float c[3] = {g.centroid.x, g.centroid.y, g.centroid.z};
#pragma unroll
  for (int k = 0; k < 3; ++k) {
    atomicMin(&bounds[k], ordered_int(c[k]));
    atomicMax(&bounds[3 + k], ordered_int(c[k]));
  }
}

__global__ void sorted_normals(uint32_t m, const uint32_t* order, const TriangleGeom* geom, Vec3* out) {
  const uint64_t k = item_index();
  if (k < m) out[k] = geom[order[k]].normal;
}

__global__ void mollify_kernel(GridView tg, const Vec3* normals, Gaussian gm, float radius, Vec3* out) {
  const uint64_t t = item_index();
  if (t < tg.count) out[t] = mollified_face_normal(tg, normals, t, gm, radius);
}

__global__ void jones_kernel(uint32_t n, const Point4* points, GridView tg, const Vec3* mollified,
                             Gaussian gs, Gaussian gr, float radius, Vec3* moved) {
  const uint64_t i = item_index();
  if (i < n) moved[i] = jones_bilateral_position(tg, mollified, xyz(points[i]), gs, gr, radius);
}

// Centroid bounds read back to lay the grid out on the host, as build_grid does.
GridLayout centroid_layout(DeviceFrame& f, float cell, cudaStream_t s) {
  int* bounds = f.bounds.reserve(6);
  FQ_LAUNCH(reset_bounds, launch_shape(1, tuning::kResetBoundsBlock), s, bounds);
  FQ_LAUNCH(centroid_points, f.m, s, f.m, f.tri_geom.data(), f.tri_in.reserve(f.m), bounds);
  int* h = f.h_bounds.reserve(6);
  FQ_CUDA_CHECK(cudaMemcpyAsync(h, bounds, 6 * sizeof(int), cudaMemcpyDeviceToHost, s));
  FQ_CUDA_CHECK(cudaStreamSynchronize(s));
  const Vec3 lo{from_ordered_int(h[0]), from_ordered_int(h[1]), from_ordered_int(h[2])};
  const Vec3 hi{from_ordered_int(h[3]), from_ordered_int(h[4]), from_ordered_int(h[5])};
  return choose_grid_layout(lo, hi, cell, f.m);
}

}  // namespace

void bilateral_filter(DeviceFrame& f, const RunPlan& run, cudaStream_t s) {
  const GridLayout layout = centroid_layout(f, run.grid_cell, s);
  build_device_grid(layout, f.tri_in.data(), f.m, f.tri_grid, f.tri_points.reserve(f.m), s);
  FQ_LAUNCH(sorted_normals, f.m, s, f.m, f.tri_grid.order.data(), f.tri_geom.data(),
            f.tri_normals.reserve(f.m));
  const GridView tg = f.tri_grid.view(f.tri_points.data());
  FQ_LAUNCH(mollify_kernel, f.m, s, tg, f.tri_normals.data(), Gaussian::with_sigma(run.mollify.sigma),
            run.mollify.radius, f.tri_mollified.reserve(f.m));
  FQ_LAUNCH(jones_kernel, f.n, s, f.n, f.points.data(), tg, f.tri_mollified.data(),
            Gaussian::with_sigma(run.sigma_s.sigma), Gaussian::with_sigma(run.sigma_r), run.sigma_s.radius,
            f.moved.reserve(f.n));
}

}  // namespace fq::cuda
