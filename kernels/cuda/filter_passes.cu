// Filter passes of the CUDA engine: one thread per vertex (grid order) or per triangle,
// each calling the same host+device math as the CPU engine (kernels/*_math.h).
#include "kernels/cuda/cuda_check.cuh"
#include "kernels/cuda/launch.cuh"
#include "kernels/cuda/passes.cuh"
#include "kernels/filter_math.h"
#include "kernels/gaussian.h"

namespace fq::cuda {

namespace {

__global__ void renumber_triangles(uint64_t count, const uint32_t* in, const uint32_t* rank, uint32_t* out) {
  const uint64_t t = item_index();
  if (t < count) out[t] = rank[in[t]];
}

__global__ void neighbourhood_kernel(GridView g, const Quadric* base, Gaussian gb, float radius,
                                     Quadric* out) {
  const uint64_t i = item_index();
  if (i < g.count) out[i] = neighbourhood_quadric(g, base, i, gb, radius);
}

__global__ void diffusion_kernel(GridView g, const Quadric* nbhd, Gaussian gs, Gaussian gr, float radius,
                                 Quadric* out) {
  const uint64_t i = item_index();
  if (i < g.count) out[i] = bilateral_quadric(g, nbhd, i, gs, gr, radius);
}

__global__ void update_kernel(GridView g, const Quadric* bl, const Vec3* vnormal, bool constrained,
                              Gaussian gn, float radius_n, float tikhonov, Vec3* moved) {
  const uint64_t i = item_index();
  if (i >= g.count) return;
  const Vec3 n = constrained ? smoothed_normal(g, vnormal, i, gn, radius_n) : Vec3{0.f, 0.f, 0.f};
  moved[i] = updated_position(xyz(g.points[i]), bl[i], constrained, n, tikhonov);
}

}  // namespace

void sort_into_grid(DeviceFrame& f, const GridLayout& layout, cudaStream_t s) {
  build_device_grid(layout, f.in_points.data(), f.n, f.grid, f.points.reserve(f.n), s);
  const uint64_t idx = 3 * uint64_t(f.m);
  FQ_LAUNCH(renumber_triangles, idx, s, idx, f.in_tris.data(), f.grid.rank.data(), f.tris.reserve(idx));
}

void neighbourhood_quadrics(DeviceFrame& f, Extent sigma_b, cudaStream_t s) {
  const GridView g = f.grid.view(f.points.data());
  FQ_LAUNCH(neighbourhood_kernel, f.n, s, g, f.base.data(), Gaussian::with_sigma(sigma_b.sigma),
            sigma_b.radius, f.nbhd.reserve(f.n));
}

void diffuse_quadrics(DeviceFrame& f, const RunPlan& run, cudaStream_t s) {
  const GridView g = f.grid.view(f.points.data());
  FQ_LAUNCH(diffusion_kernel, f.n, s, g, f.nbhd.data(), Gaussian::with_sigma(run.sigma_s.sigma),
            Gaussian::with_sigma(run.sigma_r), run.sigma_s.radius, f.bl.reserve(f.n));
}

void update_positions(DeviceFrame& f, const RunPlan& run, cudaStream_t s) {
  const GridView g = f.grid.view(f.points.data());
  const FilterParams& p = run.params.filtering;
  FQ_LAUNCH(update_kernel, f.n, s, g, f.bl.data(), f.vnormal.data(), p.constrained,
            Gaussian::with_sigma(run.sigma_n.sigma), run.sigma_n.radius, p.tikhonov, f.moved.reserve(f.n));
}

}  // namespace fq::cuda
