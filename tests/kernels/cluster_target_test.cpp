// Target cluster count, the exported link forest, clustering on the filtered geometry
// (kernels/cluster_control.h, cluster_forest.h) through the CPU engine.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "eval/noise.h"
#include "eval/sharp_edge_recall.h"
#include "io/mesh_io.h"
#include "kernels/cluster_connect.h"
#include "kernels/cluster_control.h"
#include "kernels/cluster_forest.h"
#include "kernels/cpu_engine.h"
#include "tests/support/test_meshes.h"

namespace fq {
namespace {

Mesh noisy_cube() {
  Mesh m = test::make_cube(10);
  add_gaussian_noise(m, 0.2, 5);
  return m;
}

Params clustering(float theta = 0.9f) {
  Params p;
  p.filter = false;
  p.cluster = true;
  p.filtering.sigma_s = 2.f;  // Q^bl at the paper's extents (the defaults follow qf+: 1.5, 0.7)
  p.filtering.sigma_r = 1.f;
  p.clustering.sigma_d = 2.f;
  p.clustering.sigma_q = 0.5f;
  p.clustering.theta = theta;
  return p;
}

FrameResult run(const Mesh& m, const Params& p) {
  CpuEngine engine(2);
  FrameResult out;
  const Status s = engine.process(m.view(), p, out);
  EXPECT_TRUE(s.ok()) << s.message();
  return out;
}

// The forest exported at theta = 1 gives, at every cut 1 - theta, exactly the engine's
// labels at that theta: the links do not depend on theta.
TEST(KernelClusterTarget, ForestCutReproducesEveryTheta) {
  const Mesh m = noisy_cube();
  Params uncut = clustering(1.f);
  uncut.clustering.keep_links = true;
  const FrameResult forest = run(m, uncut);
  ASSERT_EQ(forest.link_parent.size(), m.num_vertices());
  const LinkForest f{forest.link_parent.data(), forest.link_p.data(), m.num_vertices()};
  for (float theta : {0.3f, 0.6f, 0.8f, 0.9f, 0.97f, 1.f}) {
    SCOPED_TRACE(theta);
    const FrameResult direct = run(m, clustering(theta));
    std::vector<uint32_t> labels;
    EXPECT_EQ(labels_at_cut(f, 1.0f - theta, labels), direct.num_clusters);
    EXPECT_EQ(labels, direct.labels);
  }
}

TEST(KernelClusterTarget, ReachesTheTargetAndReportsItsTheta) {
  const Mesh m = noisy_cube();
  Params p = clustering();
  p.clustering.geometry = ClusterGeometry::kInput;
  uint32_t previous = 0;
  for (uint32_t target : {20u, 40u, 80u, 160u}) {
    SCOPED_TRACE(target);
    p.clustering.target_clusters = target;
    const FrameResult out = run(m, p);
    EXPECT_EQ(out.num_clusters, target);  // distinct link proximities: no ties to round over
    EXPECT_GT(out.theta, 0.f);
    EXPECT_LE(out.theta, 1.f);
    EXPECT_GT(out.num_clusters, previous);
    previous = out.num_clusters;
    for (uint32_t l : out.labels) ASSERT_LT(l, out.num_clusters);
    EXPECT_TRUE(out.link_parent.empty()) << "links are only returned on request";
    // The reported theta, given back as theta, gives the same clustering.
    const FrameResult again = run(m, clustering(out.theta));
    EXPECT_EQ(again.num_clusters, out.num_clusters);
    EXPECT_EQ(again.labels, out.labels);
  }
}

TEST(KernelClusterTarget, BelowThePermanentRootsGivesThemAll) {
  const Mesh m = noisy_cube();
  Params p = clustering();
  p.clustering.geometry = ClusterGeometry::kInput;
  p.clustering.target_clusters = 1;
  const FrameResult out = run(m, p);
  EXPECT_EQ(out.theta, 1.f);
  EXPECT_EQ(out.num_clusters, run(m, clustering(1.f)).num_clusters);
}

// With connected clusters the count after splitting and merging is found by bisection over
// the cut: close to the target, every label one piece of at least the minimum size (the
// cube is closed, so every piece has a neighbour to merge into).
TEST(KernelClusterTarget, ConnectedClustersNearTheTarget) {
  const Mesh m = noisy_cube();
  Params p = clustering();
  p.clustering.geometry = ClusterGeometry::kInput;
  p.clustering.target_clusters = 30;
  p.clustering.min_cluster_size = 10;
  const FrameResult out = run(m, p);
  EXPECT_NEAR(double(out.num_clusters), 30.0, 3.0);
  std::vector<uint32_t> size(out.num_clusters, 0);
  for (uint32_t l : out.labels) {
    ASSERT_LT(l, out.num_clusters);
    ++size[l];
  }
  for (uint32_t s : size) EXPECT_GE(s, p.clustering.min_cluster_size);
  std::vector<uint32_t> again = out.labels;
  EXPECT_EQ(connect_clusters(m.view(), again, 1), out.num_clusters) << "a label has two pieces";
}

TEST(KernelClusterTarget, FilteredGeometryKeepsTheOutputPositions) {
  const Mesh m = noisy_cube();
  Params p = clustering();
  p.clustering.geometry = ClusterGeometry::kFiltered;
  const FrameResult only_labels = run(m, p);
  EXPECT_EQ(only_labels.positions, m.positions) << "cluster-only output keeps the input positions";
  EXPECT_GT(only_labels.num_clusters, 0u);
  p.filter = true;
  const FrameResult both = run(m, p);
  Params filter_only = p;
  filter_only.cluster = false;
  EXPECT_EQ(both.positions, run(m, filter_only).positions) << "clustering must not change the filter output";
  EXPECT_EQ(both.labels, only_labels.labels);
  const bool has_cluster_pass =
      std::any_of(both.timings.begin(), both.timings.end(),
                  [](const PassTiming& t) { return t.name.starts_with("cluster."); });
  EXPECT_TRUE(has_cluster_pass);
}

// The extra runs' buffers belong to the engine (they were the calling thread's, out of reach
// of release_memory and alive as long as the thread): an idle engine gives them back.
TEST(KernelClusterTarget, ReleaseMemoryGivesBackTheExtraRuns) {
  const Mesh m = noisy_cube();
  Params p = clustering();
  p.clustering.geometry = ClusterGeometry::kFiltered;
  CpuEngine engine(2);
  FrameResult out;
  ASSERT_TRUE(engine.process(m.view(), p, out).ok());
  EXPECT_GE(engine.cluster_runs().bytes(), 2 * sizeof(float) * m.positions.size())
      << "both runs kept for the next frame";
  engine.release_memory();
  EXPECT_EQ(engine.cluster_runs().bytes(), 0u);
  FrameResult again;
  ASSERT_TRUE(engine.process(m.view(), p, again).ok());
  EXPECT_EQ(again.labels, out.labels);
  CpuEngine other(2);
  EXPECT_EQ(other.cluster_runs().bytes(), 0u) << "another engine on the same thread shares nothing";
}

TEST(KernelClusterTarget, AutoGeometryIsThePapersWithoutATarget) {
  const Mesh m = noisy_cube();
  Params p = clustering();
  EXPECT_FALSE(needs_cluster_control(p));
  p.clustering.geometry = ClusterGeometry::kInput;
  EXPECT_EQ(run(m, clustering()).labels, run(m, p).labels);
  p.clustering.target_clusters = 10;
  p.clustering.geometry = ClusterGeometry::kAuto;
  EXPECT_EQ(p.clustering.effective_geometry(), ClusterGeometry::kFiltered);
}

// The task the filtered geometry exists for: on noisy fandisk, about 60 clusters whose
// borders follow the creases, where the paper's geometry at the same count does not.
TEST(KernelClusterTarget, ClustersFollowFandiskCreasesUnderNoise) {
  Mesh clean;
  const std::string path = std::string(FQ_SOURCE_DIR) + "/data/fandisk.ply";
  ASSERT_TRUE(io::read_mesh(path, clean).ok()) << path;
  Mesh noisy = clean;
  add_gaussian_noise(noisy, 0.2, 1);
  Params p;  // defaults, as fqfilter --cluster --target-clusters 60
  p.cluster = true;
  p.clustering.target_clusters = 60;
  const FrameResult feature = run(noisy, p);
  const double recall = sharp_edge_recall(clean.view(), feature.labels.data()).recall;
  EXPECT_LE(feature.num_clusters, 80u);
  EXPECT_GE(recall, 0.9);
  p.clustering.geometry = ClusterGeometry::kInput;
  const FrameResult paper = run(noisy, p);
  EXPECT_GT(recall, sharp_edge_recall(clean.view(), paper.labels.data()).recall);
  RecordProperty("recall_filtered", std::to_string(recall));
}

}  // namespace
}  // namespace fq
