// The CUDA engine against the CPU engine on meshes made in code, its allocation
// behaviour (and memory returned after a huge frame), cancellation and its error paths.
// Without a device only the availability tests run.
#include "kernels/cuda_engine.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <thread>
#include <vector>

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
    auto e = make_engine({EngineKind::kAuto, 1, 0, {}});
    ASSERT_TRUE(e.ok());
    EXPECT_EQ((*e)->name(), "cpu");
    auto cuda = make_engine({EngineKind::kCuda, 1, 0, {}});
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
  p.filtering.sigma_s = sigma_s;
  p.filtering.sigma_r = sigma_r;
  return p;
}

Params clustering(float sigma_d, float sigma_q, float theta) {
  Params p = qf(2.f, 1.f);
  p.cluster = true;
  p.clustering.sigma_d = sigma_d;
  p.clustering.sigma_q = sigma_q;
  p.clustering.theta = theta;
  return p;
}

using CudaEngineTest = CudaTest;

TEST_F(CudaEngineTest, QuadricFilterMatchesCpu) {
  for (const Mesh& m : {noisy_sphere(), noisy_cube()}) {
    expect_parity_for_each(*cpu_, m.view(), qf(3.f, 1.f), kKernelPaths);
  }
}

// Gaussian weights through __expf in the team kernels, for several team sizes.
TEST_F(CudaEngineTest, FastExpWeightsMatchCpu) {
  for (const Params& params : {qf(3.f, 1.f), clustering(5.f, 0.8f, 0.9f)}) {
    for (const Mesh& m : {noisy_sphere(), noisy_cube(), make_triangle_soup(noisy_cube())}) {
      expect_parity_for_each(*cpu_, m.view(), params, {{1, true}, {4, true}, {32, true}});
    }
  }
}

TEST(CudaTuningOptions, TeamSizesOutsideTheKernelsAreRefused) {
  for (int team : {-2, 3, 5, 64}) {
    Status why;
    EXPECT_FALSE(make_cuda_engine(0, &why, {team, false})) << team;
    EXPECT_EQ(why.code(), StatusCode::kInvalidArgument) << team;
    EXPECT_NE(why.message().find(std::to_string(team)), std::string::npos) << why.message();
  }
}

TEST_F(CudaEngineTest, ConstrainedAndUnregularizedFilterMatchCpu) {
  Params params = qf(2.5f, 0.8f);
  params.filtering.constrained = true;
  const Mesh m = noisy_cube();
  Parity p;
  run_both(*cpu_, *gpu_, m.view(), params, p);
  expect_parity(p, params);
  params.filtering.constrained = false;
  params.filtering.tikhonov = 0.f;  // the paper's solver
  run_both(*cpu_, *gpu_, m.view(), params, p);
  expect_parity(p, params);
}

TEST_F(CudaEngineTest, BilateralBaselineMatchesCpu) {
  Params params = qf(3.f, 0.5f);
  params.filtering.method = FilterMethod::kBilateral;
  for (const Mesh& m : {noisy_sphere(), noisy_cube()}) {
    Parity p;
    run_both(*cpu_, *gpu_, m.view(), params, p);
    expect_parity(p, params);
  }
}

TEST_F(CudaEngineTest, ClusteringMatchesCpu) {
  for (const Params& params : {clustering(5.f, 0.8f, 0.9f), clustering(4.f, 1.f, 0.5f)}) {
    for (const Mesh& m : {noisy_sphere(), noisy_cube()}) {
      expect_parity_for_each(*cpu_, m.view(), params, kKernelPaths,
                             [](const Parity& p) { EXPECT_GT(p.gpu.num_clusters, 1u); });
    }
  }
  Params euclid = clustering(5.f, 1.f, 0.9f);
  euclid.clustering.method = ClusterMethod::kEuclidean;
  Parity p;
  run_both(*cpu_, *gpu_, noisy_sphere().view(), euclid, p);
  expect_parity(p, euclid);
}

// A target count (the exported link forest) and the filtered clustering geometry go through
// the same host code for both engines (kernels/cluster_control.h).
TEST_F(CudaEngineTest, TargetCountAndFilteredGeometryMatchCpu) {
  Params params = clustering(5.f, 1.f, 0.9f);
  params.clustering.target_clusters = 40;
  for (const Mesh& m : {noisy_sphere(), noisy_cube()}) {
    Parity p;
    run_both(*cpu_, *gpu_, m.view(), params, p);
    SCOPED_TRACE(p.summary());
    EXPECT_LE(p.pos.p99, 1e-4);
    // The cut falls between two link proximities; float differences may swap the two
    // nearest it, which relabels one region: agreement is high, not exact.
    EXPECT_GE(p.labels, 0.9);
    EXPECT_NEAR(double(p.gpu.num_clusters), 40.0, 1.0);
    EXPECT_GT(p.gpu.theta, 0.f);
    EXPECT_LE(p.gpu.theta, 1.f);
    EXPECT_TRUE(p.gpu.link_parent.empty());
  }
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
  expect_parity_for_each(*cpu_, soup.view(), params, kKernelPaths);
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
    expect_parity_for_each(*cpu_, m.view(), params, kKernelPaths,
                           [](const Parity& p) { EXPECT_TRUE(all_finite(p.gpu.positions)); });
  }
  params.filtering.method = FilterMethod::kBilateral;
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
  bf.filtering.method = FilterMethod::kBilateral;
  ASSERT_TRUE(gpu_->process(m.view(), bf, r).ok());
  const uint64_t after_bf = cuda_allocation_count();
  for (int k = 0; k < 3; ++k) ASSERT_TRUE(gpu_->process(m.view(), bf, r).ok());
  EXPECT_EQ(cuda_allocation_count(), after_bf);
}

// fqd runs two engines on one device when engine.gpus lists it twice: each engine on its own
// thread, CUDA stream and buffers, frames of both on the device at once. Each gives, frame after
// frame, what one engine gives alone.
TEST_F(CudaEngineTest, TwoEnginesOnOneDeviceAtOnceGiveWhatOneGivesAlone) {
  Status why;
  std::unique_ptr<Engine> second = make_cuda_engine(0, &why);
  ASSERT_TRUE(second) << why.message();
  const Mesh sphere = noisy_sphere(), cube = noisy_cube();
  const Params filter;  // qf+
  const Params cluster = clustering(5.f, 1.f, 0.9f);
  FrameResult want_sphere, want_cube;
  ASSERT_TRUE(gpu_->process(sphere.view(), filter, want_sphere).ok());
  ASSERT_TRUE(gpu_->process(cube.view(), cluster, want_cube).ok());
  ASSERT_FALSE(want_cube.labels.empty());
  std::atomic<int> differing{0}, failed{0};
  const auto frames = [&](Engine* e, const Mesh* m, const Params* p, const FrameResult* want) {
    for (int k = 0; k < 20; ++k) {
      FrameResult r;
      if (!e->process(m->view(), *p, r).ok())
        ++failed;
      else if (r.positions != want->positions || r.labels != want->labels)
        ++differing;
    }
  };
  std::thread a(frames, gpu_.get(), &sphere, &filter, &want_sphere);
  std::thread b(frames, second.get(), &cube, &cluster, &want_cube);
  a.join();
  b.join();
  EXPECT_EQ(failed.load(), 0);
  EXPECT_EQ(differing.load(), 0);
}

// A stream with its history (temporal filtering on the device): after its first two frames
// (the first has no history to follow) the device copy of the history and the step's buffers
// are reused, the copy the frame read and the one it wrote taking turns.
TEST_F(CudaEngineTest, NoDeviceAllocationOnAStreamWithItsHistoryAfterWarmUp) {
  const Mesh m = noisy_sphere();
  Params params;  // qf+
  params.filtering.temporal = 0.75f;
  TemporalHistory history;
  gpu_->set_history(&history);
  FrameResult r;
  for (int k = 0; k < 2; ++k) ASSERT_TRUE(gpu_->process(m.view(), params, r).ok());
  const uint64_t warm = cuda_allocation_count();
  for (int k = 0; k < 5; ++k) {
    ASSERT_TRUE(gpu_->process(m.view(), params, r).ok());
    EXPECT_GT(r.prior_share, 0.5f) << "the same frame again agrees with its history";
  }
  gpu_->set_history(nullptr);
  EXPECT_EQ(cuda_allocation_count(), warm);
  EXPECT_EQ(history.frames, 7u);
}

// Seam twins are welded on the host before either engine runs (kernels/seam_weld.h): the CUDA
// engine gives every twin its first copy's result, with the CPU engine's parity, alone and in a
// stream (the device's history holds the welded frame).
TEST_F(CudaEngineTest, SeamTwinsGetOneResultAsOnTheCpu) {
  std::vector<uint32_t> original;
  const Mesh m = split_along_seam(noisy_sphere(), original);
  const Params params = clustering(5.f, 0.8f, 0.9f);
  Parity p;
  run_both(*cpu_, *gpu_, m.view(), params, p);
  expect_parity(p, params);
  EXPECT_EQ(p.gpu.welded_vertices, p.cpu.welded_vertices);
  EXPECT_EQ(p.gpu.welded_vertices, m.num_vertices() - noisy_sphere().num_vertices());
  Params stream;  // qf+
  stream.filtering.temporal = 0.75f;
  TemporalHistory history;
  gpu_->set_history(&history);
  FrameResult r;
  for (int k = 0; k < 2; ++k) ASSERT_TRUE(gpu_->process(m.view(), stream, r).ok());
  gpu_->set_history(nullptr);
  EXPECT_GT(r.prior_coverage, 0.9f);
  for (const FrameResult* out : {&p.gpu, &r}) {
    for (uint32_t v = 0; v < m.num_vertices(); ++v) {
      for (int c = 0; c < 3; ++c)
        ASSERT_EQ(out->positions[3 * size_t(v) + c], out->positions[3 * size_t(original[v]) + c])
            << "vertex " << v;
    }
  }
  for (uint32_t v = 0; v < m.num_vertices(); ++v) ASSERT_EQ(p.gpu.labels[v], p.gpu.labels[original[v]]) << v;
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

// The device checks the frame; a bad one gets the CPU engine's status and message, and the
// engine goes on with the next frame.
TEST_F(CudaEngineTest, BadInputAndParametersAreRejectedWithTheCpuMessages) {
  FrameResult r, rc;
  Mesh m = noisy_cube();
  EXPECT_EQ(gpu_->process(m.view(), qf(-1.f, 1.f), r).code(), StatusCode::kInvalidArgument);
  auto expect_same_rejection = [&](const Mesh& bad) {
    const Status g = gpu_->process(bad.view(), qf(2.f, 1.f), r);
    const Status c = cpu_->process(bad.view(), qf(2.f, 1.f), rc);
    EXPECT_EQ(g.code(), StatusCode::kInvalidInput) << g.message();
    EXPECT_EQ(g.code(), c.code());
    EXPECT_EQ(g.message(), c.message());
  };
  // Two non-finite coordinates: the first one is named.
  m.positions[3 * 1000 + 2] = std::numeric_limits<float>::infinity();
  m.positions[7] = std::numeric_limits<float>::quiet_NaN();
  expect_same_rejection(m);
  m = noisy_cube();
  // Out-of-range indices in several triangles, the first of them in a later corner.
  m.triangles[size_t{3} * 2000] = m.num_vertices() + 5;
  m.triangles[3 * 50 + 2] = m.num_vertices();
  m.triangles[3 * 50 + 1] = m.num_vertices() + 1;
  expect_same_rejection(m);
  // Both faults: the coordinate is reported first, as check_mesh does.
  m.positions[100] = std::numeric_limits<float>::quiet_NaN();
  expect_same_rejection(m);
  Mesh point = make_single_triangle();
  for (float& c : point.positions) c = 1.5f;  // every edge of zero length
  expect_same_rejection(point);
  Mesh outlier = noisy_cube();
  append_isolated_vertex(outlier, {1e12f, 0.f, 0.f});  // far beyond 1e6 mean edges
  expect_same_rejection(outlier);
  Mesh empty;
  EXPECT_EQ(gpu_->process(empty.view(), qf(2.f, 1.f), r).code(), StatusCode::kInvalidInput);
  Parity p;
  run_both(*cpu_, *gpu_, noisy_cube().view(), qf(2.f, 1.f), p);
  expect_parity(p, qf(2.f, 1.f));
}

// A vertex shared by 1e5 triangles (listed out of order, some twice) beside an ordinary
// surface: the per-vertex triangle lists are sorted on the device in bounded time, in the
// CPU's order, and the frame matches the CPU engine.
TEST_F(CudaEngineTest, LargeFanMatchesCpu) {
  Mesh m = noisy_sphere();
  const uint32_t hub = m.num_vertices();
  constexpr int kRing = 64;
  const float hub_pos[3] = {0.f, 0.f, 14.f};
  m.positions.insert(m.positions.end(), hub_pos, hub_pos + 3);
  for (int k = 0; k < kRing; ++k) {
    const float a = 6.2831853f * float(k) / kRing;
    const float ring[3] = {std::cos(a), std::sin(a), 14.f + 0.1f * std::sin(3.f * a)};
    m.positions.insert(m.positions.end(), ring, ring + 3);
  }
  constexpr uint32_t kFan = 100000;
  for (uint32_t t = 0; t < kFan; ++t) {
    const uint32_t k = (t * 37u) % kRing;  // every ring pair, in scrambled order, many times
    const uint32_t tri[3] = {hub, hub + 1 + k, hub + 1 + (k + 1) % kRing};
    m.triangles.insert(m.triangles.end(), tri, tri + 3);
  }
  for (const Params& params : {qf(3.f, 1.f), clustering(4.f, 1.f, 0.8f)}) {
    expect_parity_for_each(*cpu_, m.view(), params, {CudaTuning{}},
                           [](const Parity& p) { EXPECT_TRUE(all_finite(p.gpu.positions)); });
  }
}

TEST_F(CudaEngineTest, ReportsDeviceTimePerPassAndTransfers) {
  FrameResult r;
  ASSERT_TRUE(gpu_->process(noisy_sphere().view(), clustering(5.f, 1.f, 0.9f), r).ok());
  std::vector<std::string> names;
  for (const PassTiming& t : r.timings) {
    names.push_back(t.name);
    EXPECT_GE(t.ms, 0.0) << t.name;
  }
  for (const char* want :
       {"upload", "checks", "to_normalized", "grid", "base_quadrics", "neighbourhood_quadrics", "diffusion",
        "noise", "refine", "score", "link", "modes", "output", "download", "finish"}) {
    EXPECT_NE(std::find(names.begin(), names.end(), want), names.end()) << want;
  }
}

// The CPU engine's rule for its scratch (cpu_engine.cpp), on the device: a frame under a
// quarter of the largest one's vertices makes the engine give that one's buffers back, and
// release_memory (an idle engine) gives everything back.
TEST_F(CudaEngineTest, DeviceMemoryReturnsWhenASmallFrameFollowsAHugeOne) {
  const Mesh small = noisy_sphere();     // 10,242 vertices
  Mesh huge = make_icosphere(8, 10.0f);  // 655,362 vertices
  add_gaussian_noise(huge, 0.2, 9);
  const Params params = clustering(5.f, 1.f, 0.9f);
  FrameResult r;
  ASSERT_TRUE(gpu_->process(small.view(), params, r).ok());
  const uint64_t small_bytes = cuda_device_bytes_held();
  ASSERT_TRUE(gpu_->process(huge.view(), params, r).ok());
  const uint64_t huge_bytes = cuda_device_bytes_held();
  EXPECT_GT(huge_bytes, 10 * small_bytes) << "the huge frame should have cost device memory";
  Parity p;
  run_both(*cpu_, *gpu_, small.view(), params, p);
  expect_parity(p, params);  // the small frame on fresh buffers is still right
  const uint64_t after = cuda_device_bytes_held();
  std::printf("device bytes held: %llu -> %llu -> %llu\n", static_cast<unsigned long long>(small_bytes),
              static_cast<unsigned long long>(huge_bytes), static_cast<unsigned long long>(after));
  EXPECT_LT(after, huge_bytes / 4) << "grow-only buffers kept the huge frame's memory";
  EXPECT_LE(after, 2 * small_bytes);
  // What fqd does after caps.pool_idle_s without frames: everything goes back, and the
  // next frame allocates anew.
  gpu_->release_memory();
  EXPECT_EQ(cuda_device_bytes_held(), 0u);
  run_both(*cpu_, *gpu_, small.view(), params, p);
  expect_parity(p, params);
}

// Cancellation (core/cancel_token.h) between the device passes: a token that never
// expires leaves the results as they are, a stopped one ends the frame with kCancelled, a
// deadline ends a frame with minutes of neighbour work, and the engine goes on.
TEST_F(CudaEngineTest, CancelTokenStopsFramesAndLeavesFinishedOnesAlone) {
  const Mesh m = noisy_sphere();
  const Params params = clustering(5.f, 1.f, 0.9f);
  const std::atomic<bool> never{false};
  const CancelToken open(&never, CancelToken::Clock::now() + std::chrono::hours(1));
  gpu_->set_cancel_token(&open);
  Parity p;
  run_both(*cpu_, *gpu_, m.view(), params, p);
  expect_parity(p, params);

  const std::atomic<bool> stop{true};
  const CancelToken stopped(&stop);
  gpu_->set_cancel_token(&stopped);
  FrameResult r;
  Status s = gpu_->process(m.view(), params, r);
  EXPECT_EQ(s.code(), StatusCode::kCancelled) << s.message();
  EXPECT_TRUE(r.labels.empty());

  Mesh big = make_icosphere(7, 10.0f);  // 163,842 vertices, each visiting all others per pass
  add_gaussian_noise(big, 0.2, 4);
  Params wide = params;
  wide.filtering.sigma_s = 400.f;
  wide.clustering.sigma_d = 400.f;
  const CancelToken deadline(nullptr, CancelToken::Clock::now() + std::chrono::milliseconds(50));
  gpu_->set_cancel_token(&deadline);
  s = gpu_->process(big.view(), wide, r);
  EXPECT_EQ(s.code(), StatusCode::kCancelled) << s.message();
  EXPECT_EQ(s.message(), "time limit exceeded");

  gpu_->set_cancel_token(nullptr);
  run_both(*cpu_, *gpu_, m.view(), params, p);
  expect_parity(p, params);
}

}  // namespace
}  // namespace fq::test
