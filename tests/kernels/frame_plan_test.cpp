// The frame plan (kernels/frame_plan.h): each method's passes and radii, checked by hand
// against the parameters, and the runs cluster control adds; then how Engine::process runs a
// plan: one parameter check per frame, and cluster control's extra runs made without
// re-entering process().
#include "kernels/frame_plan.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "eval/noise.h"
#include "kernels/cpu_engine.h"
#include "tests/support/param_values.h"
#include "tests/support/test_meshes.h"

namespace fq {
namespace {

using P = PassKind;

std::vector<std::string> names(const RunPlan& run) {
  std::vector<std::string> out;
  for (PassKind k : run.passes) out.emplace_back(pass_name(k));
  return out;
}

void expect_extent(Extent e, float sigma, float radius) {
  EXPECT_FLOAT_EQ(e.sigma, sigma);
  EXPECT_FLOAT_EQ(e.radius, radius);
}

TEST(KernelFramePlan, QfPlusAloneRunsNoNeighbourhoodPass) {
  const FramePlan plan = plan_frame(Params{});  // qf+, sigma_s 1.5, sigma_r 0.7
  ASSERT_EQ(plan.runs.size(), 1u);
  EXPECT_FALSE(plan.cluster_control);
  const RunPlan& r = plan.runs[0];
  EXPECT_EQ(r.role, RunRole::kFrame);
  EXPECT_EQ(names(r), (std::vector<std::string>{"grid", "base_quadrics", "noise", "refine"}));
  EXPECT_FLOAT_EQ(r.grid_cell, 1.5f);
  expect_extent(r.sigma_b, 0.75f, 1.5f);  // 0 = sigma_s / 2
  expect_extent(r.sigma_s, 1.5f, 3.f);
  expect_extent(r.sigma_n, 0.75f, 1.5f);
  expect_extent(r.sigma_d, 5.f, 10.f);
  EXPECT_FALSE(r.refinement_known());
  EXPECT_EQ(r.refinement(NoiseEstimate::white_noise(0.1f)).noise,
            plan_refinement(RefineParams{}, 0.1f).noise);
  EXPECT_STREQ(r.timing_prefix(), "");
}

TEST(KernelFramePlan, QfPlusWithAKnownNoiseIsPlannedWhole) {
  Params p;
  p.filtering.refine.known_noise = 0.2f;
  p.filtering.refine.strength = 2.f;
  const RunPlan r = plan_frame(p).runs[0];
  ASSERT_TRUE(r.refinement_known());
  EXPECT_FLOAT_EQ(r.refinement(NoiseEstimate::white_noise(0.9f)).noise, 0.4f) << "the estimate is ignored";
}

TEST(KernelFramePlan, QfDiffusesThenUpdates) {
  Params p;
  p.filtering.method = FilterMethod::kQuadric;
  p.filtering.sigma_s = 2.f;
  p.filtering.sigma_b = 0.6f;
  RunPlan r = plan_frame(p).runs[0];
  EXPECT_EQ(names(r), (std::vector<std::string>{"grid", "base_quadrics", "neighbourhood_quadrics",
                                                "diffusion", "update"}));
  EXPECT_FLOAT_EQ(r.grid_cell, 2.f);
  expect_extent(r.extent(P::kNeighbourhoodQuadrics), 0.6f, 1.2f);
  expect_extent(r.extent(P::kDiffusion), 2.f, 4.f);
  expect_extent(r.extent(P::kUpdate), 0.f, 0.f);  // unconstrained: no neighbourhood
  p.filtering.constrained = true;
  p.filtering.sigma_n = 0.4f;
  r = plan_frame(p).runs[0];
  expect_extent(r.extent(P::kUpdate), 0.4f, 0.8f);
}

TEST(KernelFramePlan, BfMollifiesAtHalfSigmaS) {
  Params p;
  p.filtering.method = FilterMethod::kBilateral;
  p.filtering.sigma_s = 3.f;
  p.filtering.sigma_r = 0.5f;
  const RunPlan r = plan_frame(p).runs[0];
  EXPECT_EQ(names(r), (std::vector<std::string>{"grid", "base_quadrics", "bilateral_filter"}));
  expect_extent(r.extent(P::kBilateralFilter), 3.f, 6.f);
  expect_extent(r.mollify, 1.5f, 3.f);
  EXPECT_FLOAT_EQ(r.sigma_r, 0.5f);
  EXPECT_FLOAT_EQ(r.grid_cell, 3.f);
}

TEST(KernelFramePlan, ClusteringOnTheInputIsOneRun) {
  Params p;
  p.cluster = true;
  p.clustering.sigma_d = 4.f;
  p.clustering.keep_links = true;
  const FramePlan plan = plan_frame(p);
  ASSERT_EQ(plan.runs.size(), 1u);
  EXPECT_FALSE(plan.cluster_control);
  const RunPlan& r = plan.runs[0];
  EXPECT_EQ(names(r),
            (std::vector<std::string>{"grid", "base_quadrics", "neighbourhood_quadrics", "diffusion", "noise",
                                      "refine", "score", "link", "modes", "export_links"}));
  expect_extent(r.extent(P::kScore), 4.f, 8.f);
  expect_extent(r.extent(P::kLink), 4.f, 8.f);
  p.clustering.min_cluster_size = 10;  // connected clusters: the same run, then cluster control
  const FramePlan connected = plan_frame(p);
  EXPECT_TRUE(connected.cluster_control);
  ASSERT_EQ(connected.runs.size(), 1u);
  EXPECT_EQ(connected.runs[0].params.clustering.min_cluster_size, 0u)
      << "the run's labels are the plain ones";
}

// A target count clusters the filtered mesh (auto geometry): the frame's filter, the
// normal-constrained geometry filter, then the clustering at half the filter's extents on it.
TEST(KernelFramePlan, FilteredGeometryAddsTheGeometryAndClusteringRuns) {
  Params p;
  p.filtering.method = FilterMethod::kQuadric;
  p.cluster = true;
  p.clustering.target_clusters = 20;
  const FramePlan plan = plan_frame(p);
  EXPECT_TRUE(plan.cluster_control);
  ASSERT_EQ(plan.runs.size(), 3u);
  const RunPlan &frame = plan.runs[0], &geometry = plan.runs[1], &clusters = plan.runs[2];
  EXPECT_EQ(frame.role, RunRole::kFrame);
  EXPECT_EQ(names(frame), (std::vector<std::string>{"grid", "base_quadrics", "neighbourhood_quadrics",
                                                    "diffusion", "update"}));
  EXPECT_EQ(geometry.role, RunRole::kGeometry);
  EXPECT_TRUE(geometry.params.filtering.constrained);
  expect_extent(geometry.extent(P::kUpdate), 0.75f, 1.5f);
  EXPECT_STREQ(geometry.timing_prefix(), "geometry.");
  EXPECT_EQ(clusters.role, RunRole::kClustering);
  EXPECT_EQ(names(clusters),
            (std::vector<std::string>{"grid", "base_quadrics", "neighbourhood_quadrics", "diffusion", "score",
                                      "link", "modes", "export_links"}));
  EXPECT_FLOAT_EQ(clusters.grid_cell, 0.75f);
  expect_extent(clusters.sigma_b, 0.375f, 0.75f);
  expect_extent(clusters.sigma_s, 0.75f, 1.5f);
  EXPECT_FLOAT_EQ(clusters.sigma_r, 0.35f);
  expect_extent(clusters.sigma_d, 5.f, 10.f);
  EXPECT_FLOAT_EQ(clusters.params.clustering.theta, 1.f) << "cut nothing: the forest gives every theta";
  EXPECT_STREQ(clusters.timing_prefix(), "cluster.");

  p.filtering.constrained = true;  // the frame's filter is the geometry filter: one run less
  const FramePlan shared = plan_frame(p);
  ASSERT_EQ(shared.runs.size(), 2u);
  EXPECT_EQ(shared.runs[1].role, RunRole::kClustering);

  for (FilterMethod m : {FilterMethod::kQuadricRefined, FilterMethod::kBilateral}) {
    p.filtering.constrained = false;  // read by "qf" only: these filters are the geometry filter
    p.filtering.method = m;
    const FramePlan two = plan_frame(p);
    ASSERT_EQ(two.runs.size(), 2u) << test::mode_name(m);
    EXPECT_EQ(two.runs[0].role, RunRole::kFrame);
    EXPECT_EQ(two.runs[1].role, RunRole::kClustering);
  }

  p.filter = false;  // labels only: the geometry run, then the clustering run
  const FramePlan labels = plan_frame(p);
  ASSERT_EQ(labels.runs.size(), 2u);
  EXPECT_EQ(labels.runs[0].role, RunRole::kGeometry);
  EXPECT_TRUE(labels.runs[0].params.filter);
}

// A noisy cube, made once for the tests below.
const Mesh& noisy_cube() {
  static const Mesh cube = [] {
    Mesh m = test::make_cube(8);
    add_gaussian_noise(m, 0.2, 5);
    return m;
  }();
  return cube;
}

// Before, cluster control called process() back for each run and every call checked the
// parameters again: 4 checks and 4 process() calls for this frame.
TEST(KernelEngineTemplate, AFrameChecksItsParametersOnceAndRunsThePlan) {
  const Mesh& m = noisy_cube();
  Params p;
  p.filtering.method = FilterMethod::kQuadric;
  p.cluster = true;
  p.clustering.target_clusters = 12;
  CpuEngine engine(2);
  FrameResult out;
  ASSERT_TRUE(engine.process(m.view(), p, out).ok());
  EXPECT_EQ(engine.counts().frames, 1u);
  EXPECT_EQ(engine.counts().validations, 1u);
  EXPECT_EQ(engine.counts().runs, 3u) << "the frame's filter, the geometry filter and the clustering run";
  std::vector<std::string> timings;
  for (const PassTiming& t : out.timings) timings.push_back(t.name);
  EXPECT_EQ(timings.front(), "normalize");
  EXPECT_NE(std::find(timings.begin(), timings.end(), "geometry.update"), timings.end());
  EXPECT_NE(std::find(timings.begin(), timings.end(), "cluster.score"), timings.end());
  EXPECT_EQ(timings.back(), "cluster_control");
  EXPECT_GT(out.num_clusters, 0u);

  ASSERT_TRUE(engine.process(m.view(), Params{}, out).ok());
  EXPECT_EQ(engine.counts().frames, 2u);
  EXPECT_EQ(engine.counts().validations, 2u);
  EXPECT_EQ(engine.counts().runs, 4u);
}

TEST(KernelEngineTemplate, BadParametersAreCheckedOnceAndRunNothing) {
  const Mesh& m = noisy_cube();
  Params p;
  p.filtering.sigma_s = -1.f;
  CpuEngine engine(2);
  FrameResult out;
  EXPECT_EQ(engine.process(m.view(), p, out).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(engine.counts().validations, 1u);
  EXPECT_EQ(engine.counts().runs, 0u);
}

// The pass sequence the engine ran is the plan's, in its order, with the plan's names.
TEST(KernelEngineTemplate, TheCpuEngineRunsThePlansPasses) {
  const Mesh& m = noisy_cube();
  for (FilterMethod method :
       {FilterMethod::kQuadricRefined, FilterMethod::kQuadric, FilterMethod::kBilateral}) {
    Params p;
    p.filtering.method = method;
    p.cluster = true;
    CpuEngine engine(2);
    FrameResult out;
    ASSERT_TRUE(engine.process(m.view(), p, out).ok());
    std::vector<std::string> ran;
    for (const PassTiming& t : out.timings) ran.push_back(t.name);
    std::vector<std::string> planned{"normalize"};
    for (const std::string& n : names(plan_frame(p).runs[0])) planned.push_back(n);
    planned.push_back("output");
    EXPECT_EQ(ran, planned) << test::mode_name(method);
  }
}

}  // namespace
}  // namespace fq
