// Results do not depend on the thread count nor on what the engine processed before:
// every per-vertex sum runs over neighbours in grid order, so positions and labels must be
// bit-identical, not merely close.
#include <gtest/gtest.h>

#include <string>

#include "kernels/cpu_engine.h"
#include "tests/kernels/frame_result_checks.h"
#include "tests/support/test_meshes.h"

namespace fq {
namespace {

using test::expect_identical;
using test::noisy;

FrameResult run(CpuEngine& engine, const Mesh& mesh, const Params& p) {
  FrameResult out;
  const Status s = engine.process(mesh.view(), p, out);
  EXPECT_TRUE(s.ok()) << s.message();
  return out;
}

std::vector<std::pair<std::string, Params>> modes() {
  Params quadric;
  quadric.cluster = true;
  quadric.clustering.sigma_d = 2.f;  // enough clusters for the labels to mean something
  quadric.clustering.sigma_q = 1.f;
  Params constrained = quadric;
  constrained.filtering.constrained = true;
  Params bilateral = quadric;
  bilateral.filtering.method = FilterMethod::kBilateral;
  bilateral.filtering.sigma_r = 1.5f;
  Params euclidean = quadric;
  euclidean.clustering.method = ClusterMethod::kEuclidean;
  return {
      {"quadric", quadric}, {"constrained", constrained}, {"bilateral", bilateral}, {"euclidean", euclidean}};
}

TEST(KernelDeterminism, ThreadCountDoesNotChangeResults) {
  const Mesh meshes[] = {noisy(test::make_icosphere(4), 1), noisy(test::make_cube(10), 2)};
  CpuEngine one(1), two(2), three(3);
  ASSERT_EQ(three.threads(), 3);
  for (const Mesh& m : meshes) {
    for (const auto& [name, p] : modes()) {
      const FrameResult a = run(one, m, p);
      ASSERT_GT(a.num_clusters, 3u) << name;
      expect_identical(a, run(two, m, p), name + " 1 vs 2 threads");
      expect_identical(a, run(three, m, p), name + " 1 vs 3 threads");
    }
  }
}

// The engine keeps its buffers between frames; a frame after a bigger or a smaller one
// must come out exactly as on a fresh engine.
TEST(KernelDeterminism, ReusedEngineMatchesAFreshOne) {
  const Mesh small = noisy(test::make_cube(5), 3), big = noisy(test::make_icosphere(4), 4);
  Params p;
  p.cluster = true;
  CpuEngine fresh_small(2), fresh_big(2), reused(2);
  const FrameResult want_small = run(fresh_small, small, p), want_big = run(fresh_big, big, p);
  expect_identical(run(reused, small, p), want_small, "small first");
  expect_identical(run(reused, big, p), want_big, "big after small");
  expect_identical(run(reused, small, p), want_small, "small after big");
  Params bf = p;
  bf.filtering.method = FilterMethod::kBilateral;
  run(reused, big, bf);
  expect_identical(run(reused, small, p), want_small, "quadric after bilateral");
}

}  // namespace
}  // namespace fq
