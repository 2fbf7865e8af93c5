// "qf+" on the CUDA engine against the CPU engine: the noise estimate (the same samples, the
// same host reduction) and the filtered positions, on noisy and clean synthetic shapes, with a
// given noise and strength, with fractional rounds, with clustering beside it (every kernel
// path of the quadric passes), and on the shared real meshes (FQ_MESH_DIR). Skips without a
// device.
#include <gtest/gtest.h>

#include <cmath>

#include "eval/noise.h"
#include "io/mesh_io.h"
#include "tests/cuda/parity.h"
#include "tests/support/mesh_dir.h"
#include "tests/support/test_meshes.h"

namespace fq::test {
namespace {

class CudaRefineParity : public CudaTest {};

// Both engines' estimates: the samples are the same math in double precision on both sides,
// reduced on the host by the same code; contraction into fused multiply-adds on the device
// leaves them within 1e-4 of each other (relative).
void expect_same_noise(const Parity& p) {
  EXPECT_NEAR(p.gpu.noise_estimate, p.cpu.noise_estimate, 1e-4f * std::fmax(p.cpu.noise_estimate, 1e-3f));
  EXPECT_NEAR(p.gpu.filter_noise, p.cpu.filter_noise, 1e-4f * std::fmax(p.cpu.filter_noise, 1e-3f));
}

const std::initializer_list<CudaTuning> kDefault = {{CudaTuning::kTeamBySize, false}};

TEST_F(CudaRefineParity, NoisyCubeAndSphere) {
  Mesh shapes[] = {make_cube(16), make_icosphere(5)};
  for (Mesh& m : shapes) {
    for (double s : {0.05, 0.3}) {
      Mesh noisy = m;
      add_gaussian_noise(noisy, s, 7);
      expect_parity_for_each(*cpu_, noisy.view(), Params{}, kDefault, expect_same_noise);
    }
  }
}

TEST_F(CudaRefineParity, CleanShapes) {
  Mesh shapes[] = {make_cube(16), make_icosphere(5)};
  for (Mesh& m : shapes) expect_parity_for_each(*cpu_, m.view(), Params{}, kDefault, expect_same_noise);
}

// A given noise, a strength, and a noise whose plan has a fractional last round (1 + 16σ²
// rounds: 3.56 at σ = 0.4).
TEST_F(CudaRefineParity, GivenNoiseStrengthAndFractionalRounds) {
  Mesh m = make_icosphere(5);
  add_gaussian_noise(m, 0.3, 9);
  Params given;
  given.filtering.refine.known_noise = 0.4f;
  expect_parity_for_each(*cpu_, m.view(), given, kDefault, expect_same_noise);
  Params strong;
  strong.filtering.refine.strength = 1.7f;
  expect_parity_for_each(*cpu_, m.view(), strong, kDefault, expect_same_noise);
}

// Clustering beside "qf+": the quadric passes run for the labels, under every kernel path.
TEST_F(CudaRefineParity, WithClustering) {
  Mesh m = make_cube(16);
  add_gaussian_noise(m, 0.2, 7);
  Params p;
  p.cluster = true;
  expect_parity_for_each(*cpu_, m.view(), p, kKernelPaths, expect_same_noise);
}

TEST_F(CudaRefineParity, RealMeshesWithNoise) {
  for (const char* file : {"fandisk.ply", "bunny.ply", "igea.ply", "crane/crane_0060.drc"}) {
    const auto path = find_mesh(file);
    if (!path) GTEST_SKIP() << file << " not found in " << mesh_dir();
    Mesh mesh;
    const Status rs = io::read_mesh(*path, mesh);
    ASSERT_TRUE(rs.ok()) << rs.message();
    for (double s : {0.05, 0.2}) {
      Mesh noisy = mesh;
      add_gaussian_noise(noisy, s, 7);
      std::printf("  %s (%u vertices), noise %.2f:\n", file, mesh.num_vertices(), s);
      expect_parity_for_each(*cpu_, noisy.view(), Params{}, kDefault, expect_same_noise);
    }
  }
}

// Temporal filtering (kernels/temporal.h) runs on the host after either engine: a stream of
// frames through each engine with its own history gives the same results within the stated
// tolerances, frame after frame, with the same pull towards the history.
TEST_F(CudaRefineParity, TemporalSequence) {
  const Mesh sphere = make_icosphere(5);
  Params p;
  p.filtering.temporal = 0.75f;
  TemporalHistory cpu_history, gpu_history;
  cpu_->set_history(&cpu_history);
  gpu_->set_history(&gpu_history);
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    Mesh frame = sphere;
    add_gaussian_noise(frame, 0.2, seed);
    Parity r;
    run_both(*cpu_, *gpu_, frame.view(), p, r);
    expect_parity(r, p);
    EXPECT_NEAR(r.gpu.prior_share, r.cpu.prior_share, 0.01f) << "frame " << seed;
    EXPECT_EQ(r.gpu.prior_coverage > 0.f, seed > 1);
  }
  cpu_->set_history(nullptr);
  gpu_->set_history(nullptr);
  EXPECT_EQ(gpu_history.frames, 4u);
}

}  // namespace
}  // namespace fq::test
