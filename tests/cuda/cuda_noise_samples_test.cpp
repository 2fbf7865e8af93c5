// The noise estimate's samples made on the device a warp per fit (kernels/cuda/noise_samples.cu)
// against noise_sample() on the host, sample by sample: the same failed fits (NaN fields) and the
// same values, on synthetic shapes, a fan whose 2-ring passes kMaxRing, a mesh with boundaries,
// an unreferenced vertex and zero-area triangles, and the shared real meshes with noise.
#include <cuda_runtime.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "eval/noise.h"
#include "kernels/cuda/noise_samples.cuh"
#include "kernels/frame_prep.h"
#include "kernels/vertex_faces.h"
#include "tests/cuda/parity.h"
#include "tests/cuda/real_meshes.h"
#include "tests/support/test_meshes.h"

namespace fq::test {
namespace {

class CudaNoiseSamples : public CudaTest {};

template <class T>
struct OnDevice {
  T* p = nullptr;
  explicit OnDevice(const std::vector<T>& host) {
    EXPECT_EQ(cudaMalloc(&p, std::max<size_t>(1, host.size()) * sizeof(T)), cudaSuccess);
    EXPECT_EQ(cudaMemcpy(p, host.data(), host.size() * sizeof(T), cudaMemcpyHostToDevice), cudaSuccess);
  }
  explicit OnDevice(size_t n) { EXPECT_EQ(cudaMalloc(&p, std::max<size_t>(1, n) * sizeof(T)), cudaSuccess); }
  ~OnDevice() { cudaFree(p); }
  OnDevice(const OnDevice&) = delete;
  OnDevice& operator=(const OnDevice&) = delete;
};

// Positions in mean edge lengths, as the engines hand them to the estimate.
std::vector<Vec3> normalized_positions(const Mesh& m) {
  const double edge = mean_edge_length(m.view());
  const float scale = edge > 0.0 ? float(1.0 / edge) : 1.f;
  std::vector<Vec3> x(m.num_vertices());
  for (uint32_t v = 0; v < m.num_vertices(); ++v) x[v] = scale * vertex(m, v);
  return x;
}

bool same_value(float cpu, float gpu) {
  if (std::isnan(cpu) || std::isnan(gpu)) return std::isnan(cpu) && std::isnan(gpu);
  return std::fabs(cpu - gpu) <= 1e-4f * std::fmax(1.f, std::fabs(cpu));
}

bool same_vec(Vec3 cpu, Vec3 gpu) {
  return same_value(cpu.x, gpu.x) && same_value(cpu.y, gpu.y) && same_value(cpu.z, gpu.z);
}

// Every sample of `m` (every vertex when stride is 1) on both sides; returns the usable ones.
int expect_same_samples(const Mesh& m, const std::string& what) {
  SCOPED_TRACE(what);
  const uint32_t n = static_cast<uint32_t>(m.num_vertices());
  std::vector<uint32_t> offsets, faces;
  build_vertex_faces(m.triangles.data(), m.num_triangles(), n, offsets, faces);
  const std::vector<Vec3> x = normalized_positions(m);
  const FanView host{m.triangles.data(), offsets.data(), faces.data()};
  const uint32_t stride = noise_sample_stride(n), count = noise_sample_count(n);
  OnDevice<uint32_t> d_tris(m.triangles), d_offsets(offsets), d_faces(faces);
  OnDevice<Vec3> d_x(x);
  OnDevice<NoiseSample> d_out(count);
  cuda::noise_samples(FanView{d_tris.p, d_offsets.p, d_faces.p}, d_x.p, stride, count, d_out.p, nullptr);
  std::vector<NoiseSample> gpu(count);
  EXPECT_EQ(cudaMemcpy(gpu.data(), d_out.p, count * sizeof(NoiseSample), cudaMemcpyDeviceToHost),
            cudaSuccess);
  int usable = 0, differing = 0;
  for (uint32_t k = 0; k < count; ++k) {
    const NoiseSample c = noise_sample(host, x.data(), k * stride), g = gpu[k];
    const bool same = same_value(c.z_v, g.z_v) && same_value(c.z_u, g.z_u) &&
                      same_value(c.white_correlation, g.white_correlation) &&
                      same_value(c.height, g.height) && same_vec(c.normal, g.normal) &&
                      same_vec(c.slide, g.slide);
    if (!same && ++differing <= 5)
      ADD_FAILURE() << "sample " << k << " (vertex " << k * stride << "): host " << c.z_v << " " << c.z_u
                    << " " << c.white_correlation << ", device " << g.z_v << " " << g.z_u << " "
                    << g.white_correlation;
    usable += std::isfinite(c.white_correlation) ? 1 : 0;
  }
  EXPECT_EQ(differing, 0) << "of " << count << " samples";
  return usable;
}

// A disk around one vertex of `spokes` triangles, `rings` rings deep: the centre's 1-ring has
// `spokes` vertices, its 2-ring twice as many (more than kMaxRing for spokes >= 25).
Mesh polar_disk(int spokes, int rings) {
  Mesh m;
  m.positions = {0.f, 0.f, 0.f};
  for (int r = 1; r <= rings; ++r)
    for (int s = 0; s < spokes; ++s) {
      const double a = 2 * M_PI * (s + 0.5 * (r % 2)) / spokes;
      m.positions.insert(m.positions.end(),
                         {float(r * std::cos(a)), float(r * std::sin(a)), float(0.05 * r * r)});
    }
  auto at = [&](int r, int s) { return r == 0 ? 0u : uint32_t(1 + (r - 1) * spokes + (s % spokes)); };
  for (int s = 0; s < spokes; ++s) m.triangles.insert(m.triangles.end(), {at(0, 0), at(1, s), at(1, s + 1)});
  for (int r = 1; r < rings; ++r)
    for (int s = 0; s < spokes; ++s) {
      m.triangles.insert(m.triangles.end(), {at(r, s), at(r + 1, s), at(r + 1, s + 1)});
      m.triangles.insert(m.triangles.end(), {at(r, s), at(r + 1, s + 1), at(r, s + 1)});
    }
  return m;
}

TEST_F(CudaNoiseSamples, SyntheticShapesWithAndWithoutNoise) {
  for (double s : {0.0, 0.05, 0.3}) {
    Mesh shapes[] = {make_icosphere(4), make_cube(12), make_plane_grid(40, 30)};
    for (Mesh& m : shapes) {
      if (s > 0) add_gaussian_noise(m, s, 11);
      EXPECT_GT(expect_same_samples(m, "noise " + std::to_string(s)), 100);
    }
  }
}

// The fan's centre fills its ring to kMaxRing; the rim's vertices have too few neighbours;
// the unreferenced vertex has no fan; zero-area triangles make coincident corners.
TEST_F(CudaNoiseSamples, FullRingsBoundariesAndDegenerateInput) {
  Mesh disk = polar_disk(40, 6);
  add_gaussian_noise(disk, 0.1, 3);
  append_isolated_vertex(disk, Vec3{9.f, 9.f, 9.f});
  EXPECT_GT(expect_same_samples(disk, "disk"), 40);
  Mesh cube = make_cube(8);
  append_zero_area_faces(cube, 20);
  add_gaussian_noise(cube, 0.2, 5);
  EXPECT_GT(expect_same_samples(cube, "cube with zero-area faces"), 100);
  expect_same_samples(make_non_manifold_fin(), "fin");
  expect_same_samples(make_single_triangle(), "one triangle");
}

TEST_F(CudaNoiseSamples, RealMeshesWithNoise) {
  for (const char* file : kRealMeshes) {
    std::optional<Mesh> mesh = read_real_mesh(file);
    if (!mesh) GTEST_SKIP() << file << " not found in " << mesh_dir();
    add_gaussian_noise(*mesh, 0.2, 7);
    EXPECT_GT(expect_same_samples(*mesh, file), 500);
  }
}

}  // namespace
}  // namespace fq::test
