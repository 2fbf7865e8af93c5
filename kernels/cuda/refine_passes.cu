// "qf+" passes of the CUDA engine: one thread per vertex or triangle (the noise samples: a warp
// per fit, kernels/cuda/noise_samples.cu), each calling
// the host+device math of kernels/noise_estimate.h and kernels/refine_math.h exactly as
// cpu_stages.cpp does.
#include <utility>

#include "kernels/cuda/cuda_check.cuh"
#include "kernels/cuda/launch.cuh"
#include "kernels/cuda/noise_samples.cuh"
#include "kernels/cuda/refine_passes.cuh"

namespace fq::cuda {

namespace {

__global__ void input_positions_kernel(uint32_t n, const Point4* in, Vec3* out) {
  const uint64_t v = item_index();
  if (v < n) out[v] = xyz(in[v]);
}

__global__ void closed_fan_kernel(uint32_t n, FanView fan, uint8_t* closed) {
  const uint64_t v = item_index();
  if (v < n) closed[v] = closed_fan(fan, v) ? 1 : 0;
}

__global__ void face_geometry_kernel(uint32_t m, const uint32_t* tris, const Vec3* x, TriangleGeom* geom,
                                     Vec3* normals) {
  const uint64_t t = item_index();
  if (t >= m) return;
  const uint32_t* tri = tris + 3 * size_t(t);
  geom[t] = triangle_geom(x[tri[0]], x[tri[1]], x[tri[2]]);
  normals[t] = geom[t].normal;
}

__global__ void normal_filter_kernel(uint32_t m, FanView fan, const TriangleGeom* geom, const Vec3* in,
                                     Gaussian gs, Gaussian gr, float share, Vec3* out) {
  const uint64_t t = item_index();
  if (t < m) out[t] = partial_normal(in[t], filtered_face_normal(fan, geom, in, t, gs, gr), share);
}

__global__ void free_directions_kernel(uint32_t n, FanView fan, const Vec3* normals, const uint8_t* closed,
                                       FreeDirections* out) {
  const uint64_t v = item_index();
  if (v < n) out[v] = free_directions(fan, normals, v, closed[v] != 0);
}

__global__ void vertex_update_kernel(uint32_t n, FanView fan, const Vec3* x, const Vec3* normals,
                                     const FreeDirections* dirs, float tangential_step, float share,
                                     Vec3* out) {
  const uint64_t v = item_index();
  if (v < n)
    out[v] = partial_position(x[v], updated_vertex(fan, x, normals, v, dirs[v], tangential_step), share);
}

__global__ void partial_round_kernel(uint32_t n, const Vec3* before, float share, Vec3* x) {
  const uint64_t v = item_index();
  if (v < n) x[v] = partial_position(before[v], x[v], share);
}

__global__ void tangential_move_kernel(uint32_t n, FanView fan, const Point4* in, const Vec3* x,
                                       Vec3 direction, Vec3* t, SlideLevel* level) {
  const uint64_t v = item_index();
  if (v >= n) return;
  const Vec3 normal = vertex_normal(fan, x, v);
  t[v] = tangential_move(xyz(in[v]), x[v], normal);
  level[v] = slide_level(fan, in, x, v, t[v], normal, direction);
}

__global__ void ring_mean_kernel(uint32_t n, FanView fan, const SlideLevel* in, SlideLevel* out) {
  const uint64_t v = item_index();
  if (v < n) out[v] = ring_mean(fan, in, v);
}

__global__ void limit_kernel(uint32_t n, const Vec3* t, const SlideLevel* level, float per_turn,
                             float directional, Vec3* x) {
  const uint64_t v = item_index();
  if (v < n)
    x[v] = limited_position(x[v], t[v], level[v].energy, slide_allowance(level[v], per_turn, directional));
}

}  // namespace

NoiseEstimate estimate_noise(DeviceFrame& f, RefineBuffers& b, cudaStream_t s) {
  const uint32_t n = f.n;
  const FanView fan{f.tris.data(), f.vf_start.data(), f.vf_faces.data()};
  Vec3* x = f.moved.reserve(n);
  FQ_LAUNCH(input_positions_kernel, n, s, n, f.points.data(), x);
  const uint32_t stride = noise_sample_stride(n), count = noise_sample_count(n);
  NoiseSample* samples = b.samples.reserve(count);
  noise_samples(fan, x, stride, count, samples, s);
  NoiseSample* h = b.h_samples.reserve(count);
  FQ_CUDA_CHECK(cudaMemcpyAsync(h, samples, count * sizeof(NoiseSample), cudaMemcpyDeviceToHost, s));
  FQ_CUDA_CHECK(cudaStreamSynchronize(s));
  return estimate_noise(h, count);
}

void refine_positions(DeviceFrame& f, RefineBuffers& b, const RefinePlan& plan, cudaStream_t s) {
  const uint32_t n = f.n, m = f.m;
  const FanView fan{f.tris.data(), f.vf_start.data(), f.vf_faces.data()};
  b.x.reserve(n);
  uint8_t* closed = b.closed.reserve(n);
  FQ_LAUNCH(closed_fan_kernel, n, s, n, fan, closed);
  Vec3* normals[2] = {b.normals[0].reserve(m), b.normals[1].reserve(m)};
  TriangleGeom* geom = b.geom.reserve(m);
  FreeDirections* dirs = b.dirs.reserve(n);
  const Passes rounds = plan.rounds, filters = plan.normal_passes, updates = plan.vertex_passes;
  for (int round = 0; round < rounds.count; ++round) {
    const float round_share = round == rounds.count - 1 ? rounds.last : 1.f;
    if (round_share < 1.f)
      FQ_CUDA_CHECK(
          cudaMemcpyAsync(b.round.reserve(n), f.moved.data(), n * sizeof(Vec3), cudaMemcpyDeviceToDevice, s));
    FQ_LAUNCH(face_geometry_kernel, m, s, m, f.tris.data(), f.moved.data(), geom, normals[0]);
    for (int it = 0; it < filters.count; ++it) {
      const float share = it == filters.count - 1 ? filters.last : 1.f;
      FQ_LAUNCH(normal_filter_kernel, m, s, m, fan, geom, normals[it & 1], plan.gs, plan.gr, share,
                normals[(it + 1) & 1]);
    }
    const Vec3* filtered = normals[filters.count & 1];
    FQ_LAUNCH(free_directions_kernel, n, s, n, fan, filtered, closed, dirs);
    for (int it = 0; it < updates.count; ++it) {
      const float share = it == updates.count - 1 ? updates.last : 1.f;
      FQ_LAUNCH(vertex_update_kernel, n, s, n, fan, f.moved.data(), filtered, dirs, plan.tangential_step,
                share, b.x.data());
      std::swap(f.moved, b.x);
    }
    if (round_share < 1.f) {
      FQ_LAUNCH(partial_round_kernel, n, s, n, b.round.data(), round_share, f.moved.data());
    }
  }
  Vec3* tangent = b.tangent.reserve(n);
  SlideLevel* energy[2] = {b.energy[0].reserve(n), b.energy[1].reserve(n)};
  FQ_LAUNCH(tangential_move_kernel, n, s, n, fan, f.points.data(), f.moved.data(), plan.noise_direction,
            tangent, energy[0]);
  for (int pass = 0; pass < kEnergyPasses; ++pass) {
    FQ_LAUNCH(ring_mean_kernel, n, s, n, fan, energy[pass & 1], energy[(pass + 1) & 1]);
  }
  FQ_LAUNCH(limit_kernel, n, s, n, tangent, energy[kEnergyPasses & 1], plan.tangential_allowance,
            plan.directional_allowance, f.moved.data());
}

}  // namespace fq::cuda
