// The CUDA engine against the CPU engine on meshes made in code, its allocation
// behaviour and its error paths. Without a device only the availability tests run.
#include "kernels/cuda_engine.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "eval/noise.h"
#include "tests/cuda/parity.h"
#include "tests/support/test_meshes.h"

namespace fq::test {
namespace {

TEST(CudaAvailability, EngineIsNamedOrUnavailableWithAReason) {
  Status why;
  auto gpu = make_cuda_engine(0, &why);
  if (gpu) {
    EXPECT_TRUE(why.ok());
    EXPECT_EQ(gpu->name().rfind("cuda:", 0), 0u) << gpu->name();
    EXPECT_GT(gpu->name().size(), 5u);
  } else {
    EXPECT_EQ(why.code(), StatusCode::kUnavailable);
    EXPECT_FALSE(why.message().empty());
    // auto falls back to the CPU engine; an explicit request reports the reason.
    auto e = make_engine({EngineKind::kAuto, 1, 0});
    ASSERT_TRUE(e.ok());
    EXPECT_EQ((*e)->name(), "cpu");
    auto cuda = make_engine({EngineKind::kCuda, 1, 0});
    EXPECT_FALSE(cuda.ok());
    EXPECT_EQ(cuda.status().code(), StatusCode::kUnavailable);
  }
}

TEST(CudaAvailability, BadDeviceOrdinalIsUnavailable) {
  Status why;
  EXPECT_FALSE(make_cuda_engine(4096, &why));
  EXPECT_EQ(why.code(), StatusCode::kUnavailable);
  EXPECT_FALSE(why.message().empty());
}

Mesh noisy_sphere() {
  Mesh m = make_icosphere(5, 10.0f);  // 10242 vertices
  add_gaussian_noise(m, 0.2, 7);
  return m;
}

Mesh noisy_cube() {
  Mesh m = make_cube(24, 5.0f);  // 3458 vertices, sharp edges
  add_gaussian_noise(m, 0.15, 11);
  return m;
}

Params qf(float sigma_s, float sigma_r) {
  Params p;
  p.f.sigma_s = sigma_s;
  p.f.sigma_r = sigma_r;
  return p;
}

Params clustering(float sigma_d, float sigma_q, float theta) {
  Params p = qf(2.f, 1.f);
  p.cluster = true;
  p.c.sigma_d = sigma_d;
  p.c.sigma_q = sigma_q;
  p.c.theta = theta;
  return p;
}

using CudaEngineTest = CudaTest;

TEST_F(CudaEngineTest, QuadricFilterMatchesCpu) {
  for (const Mesh& m : {noisy_sphere(), noisy_cube()}) {
    expect_parity_for_each(*cpu_, *gpu_, m.view(), qf(3.f, 1.f), "FQ_CUDA_TEAM", kKernelPaths);
  }
}

// Gaussian weights through __expf in the team kernels, for several team sizes.
TEST_F(CudaEngineTest, FastExpWeightsMatchCpu) {
  ScopedEnv fast("FQ_CUDA_FAST_EXP", "1");
  for (const Params& params : {qf(3.f, 1.f), clustering(5.f, 0.8f, 0.9f)}) {
    for (const Mesh& m : {noisy_sphere(), noisy_cube(), make_triangle_soup(noisy_cube())}) {
      expect_parity_for_each(*cpu_, *gpu_, m.view(), params, "FQ_CUDA_TEAM", {"1", "4", "32"});
    }
  }
}

// Base quadrics by per-vertex gather (default) and by float4 atomics per triangle.
TEST_F(CudaEngineTest, BothBaseQuadricVariantsMatchCpu) {
  const Params params = clustering(4.f, 1.f, 0.8f);
  for (const Mesh& m : {noisy_sphere(), noisy_cube()}) {
    expect_parity_for_each(*cpu_, *gpu_, m.view(), params, "FQ_CUDA_BASE", {"gather", "atomic"});
  }
}

TEST_F(CudaEngineTest, ConstrainedAndUnregularizedFilterMatchCpu) {
  Params params = qf(2.5f, 0.8f);
  params.f.constrained = true;
  const Mesh m = noisy_cube();
  Parity p;
  run_both(*cpu_, *gpu_, m.view(), params, p);
  expect_parity(p, params);
  params.f.constrained = false;
  params.f.tikhonov = 0.f;  // the paper's solver
  run_both(*cpu_, *gpu_, m.view(), params, p);
  expect_parity(p, params);
}

TEST_F(CudaEngineTest, BilateralBaselineMatchesCpu) {
  Params params = qf(3.f, 0.5f);
  params.f.method = FilterMethod::kBilateral;
  for (const Mesh& m : {noisy_sphere(), noisy_cube()}) {
    Parity p;
    run_both(*cpu_, *gpu_, m.view(), params, p);
    expect_parity(p, params);
  }
}

TEST_F(CudaEngineTest, ClusteringMatchesCpu) {
  for (const Params& params : {clustering(5.f, 0.8f, 0.9f), clustering(4.f, 1.f, 0.5f)}) {
    for (const Mesh& m : {noisy_sphere(), noisy_cube()}) {
      expect_parity_for_each(*cpu_, *gpu_, m.view(), params, "FQ_CUDA_TEAM", kKernelPaths,
                             [](const Parity& p) { EXPECT_GT(p.gpu.num_clusters, 1u); });
    }
  }
  Params euclid = clustering(5.f, 1.f, 0.9f);
  euclid.c.method = ClusterMethod::kEuclidean;
  Parity p;
  run_both(*cpu_, *gpu_, noisy_sphere().view(), euclid, p);
  expect_parity(p, euclid);
}

TEST_F(CudaEngineTest, ClusterOnlyKeepsInputPositions) {
  Params params = clustering(5.f, 1.f, 0.9f);
  params.filter = false;
  Parity p;
  run_both(*cpu_, *gpu_, noisy_cube().view(), params, p);
  expect_parity(p, params);
}

// Coincident vertices (as a quantized scan has) give exactly tied scores: the tie-break by
// sorted index must agree with the CPU, which needs the same order inside each cell. (The
// surface is noisy so that only the coincident vertices tie: on a perfect sphere every
// score is equal up to rounding and the clustering is decided by rounding alone.)
TEST_F(CudaEngineTest, TriangleSoupWithTiesMatchesCpu) {
  Mesh sphere = make_icosphere(3, 5.0f);
  add_gaussian_noise(sphere, 0.2, 5);
  const Mesh soup = make_triangle_soup(sphere);
  const Params params = clustering(4.f, 1.f, 0.8f);
  expect_parity_for_each(*cpu_, *gpu_, soup.view(), params, "FQ_CUDA_TEAM", kKernelPaths);
}

// Unusual meshes (as tests/kernels/degenerate_input_test.cpp feeds the CPU engine): the
// device must give the CPU engine's answer, finite, for every kernel path.
TEST_F(CudaEngineTest, UnusualMeshesMatchCpu) {
  // Noise, so that scores do not tie everywhere (exact symmetry leaves the clustering to
  // rounding, which differs between any two compilers).
  Mesh with_isolated = make_cube(6, 2.0f);
  add_gaussian_noise(with_isolated, 0.1, 21);
  append_isolated_vertex(with_isolated, {0.1f, 0.2f, 0.3f});
  append_isolated_vertex(with_isolated, {9.f, 9.f, 9.f});
  Mesh with_zero_area = make_icosphere(3, 4.0f);
  add_gaussian_noise(with_zero_area, 0.1, 22);
  append_zero_area_faces(with_zero_area, 40);
  Mesh plane = make_plane_grid(20, 12);
  add_gaussian_noise(plane, 0.1, 23);
  const Mesh meshes[] = {make_single_triangle(), make_non_manifold_fin(), plane, with_isolated,
                         with_zero_area};
  Params params = clustering(3.f, 1.f, 0.9f);
  for (const Mesh& m : meshes) {
    expect_parity_for_each(*cpu_, *gpu_, m.view(), params, "FQ_CUDA_TEAM", kKernelPaths,
                           [](const Parity& p) { EXPECT_TRUE(all_finite(p.gpu.positions)); });
  }
  params.f.method = FilterMethod::kBilateral;
  for (const Mesh& m : meshes) {
    Parity p;
    run_both(*cpu_, *gpu_, m.view(), params, p);
    expect_parity(p, params);
  }
}

TEST_F(CudaEngineTest, NoDeviceAllocationAfterWarmUp) {
  const Mesh m = noisy_sphere();
  const Params params = clustering(5.f, 1.f, 0.9f);
  FrameResult r;
  ASSERT_TRUE(gpu_->process(m.view(), params, r).ok());  // warm-up: allocates
  const uint64_t warm = cuda_allocation_count();
  EXPECT_GT(warm, 0u);
  for (int k = 0; k < 5; ++k) ASSERT_TRUE(gpu_->process(m.view(), params, r).ok());
  EXPECT_EQ(cuda_allocation_count(), warm);
  // Smaller work on the same buffers (filter only, BF) needs nothing new either.
  Params bf = qf(3.f, 1.f);
  bf.f.method = FilterMethod::kBilateral;
  ASSERT_TRUE(gpu_->process(m.view(), bf, r).ok());
  const uint64_t after_bf = cuda_allocation_count();
  for (int k = 0; k < 3; ++k) ASSERT_TRUE(gpu_->process(m.view(), bf, r).ok());
  EXPECT_EQ(cuda_allocation_count(), after_bf);
}

TEST_F(CudaEngineTest, LaunchFailureIsReportedAndEngineRecovers) {
  const Mesh m = noisy_cube();
  const Params params = clustering(4.f, 1.f, 0.9f);
  FrameResult r;
  cuda_fail_next_launch_for_testing();
  const Status s = gpu_->process(m.view(), params, r);
  EXPECT_EQ(s.code(), StatusCode::kInternal);
  // The CUDA error's name, the failed launch and where it was made.
  EXPECT_NE(s.message().find("cudaError"), std::string::npos) << s.message();
  EXPECT_NE(s.message().find("launch of "), std::string::npos) << s.message();
  EXPECT_NE(s.message().find(".cu:"), std::string::npos) << s.message();
  EXPECT_EQ(s.message().find("context is lost"), std::string::npos) << s.message();
  EXPECT_TRUE(r.labels.empty());
  Parity p;
  run_both(*cpu_, *gpu_, m.view(), params, p);
  expect_parity(p, params);
}

TEST_F(CudaEngineTest, BadInputAndParametersAreRejectedBeforeTheDevice) {
  Mesh m = noisy_cube();
  FrameResult r;
  Params bad = qf(-1.f, 1.f);
  EXPECT_EQ(gpu_->process(m.view(), bad, r).code(), StatusCode::kInvalidArgument);
  m.positions[7] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(gpu_->process(m.view(), qf(2.f, 1.f), r).code(), StatusCode::kInvalidInput);
  m.positions[7] = 0.5f;
  m.triangles[4] = m.num_vertices();
  EXPECT_EQ(gpu_->process(m.view(), qf(2.f, 1.f), r).code(), StatusCode::kInvalidInput);
  EXPECT_TRUE(gpu_->process(noisy_cube().view(), qf(2.f, 1.f), r).ok());
}

TEST_F(CudaEngineTest, ReportsDeviceTimePerPassAndTransfers) {
  FrameResult r;
  ASSERT_TRUE(gpu_->process(noisy_sphere().view(), clustering(5.f, 1.f, 0.9f), r).ok());
  std::vector<std::string> names;
  for (const PassTiming& t : r.timings) {
    names.push_back(t.name);
    EXPECT_GE(t.ms, 0.0) << t.name;
  }
  for (const char* want : {"upload", "grid", "base_quadrics", "neighbourhood_quadrics", "diffusion", "update",
                           "score", "link", "modes", "download"}) {
    EXPECT_NE(std::find(names.begin(), names.end(), want), names.end()) << want;
  }
}

}  // namespace
}  // namespace fq::test
