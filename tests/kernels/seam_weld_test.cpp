// Seam twins (kernels/seam_weld.h) through the CPU engine: a surface cut open along a seam, as an
// export leaves a UV seam, is filtered as the uncut surface, every twin given one result in the
// input's order and count; a mesh without twins takes the path it took before, bit for bit.
#include "kernels/seam_weld.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "eval/noise.h"
#include "kernels/cpu_engine.h"
#include "kernels/frame_prep.h"
#include "tests/kernels/frame_result_checks.h"
#include "tests/support/param_values.h"
#include "tests/support/test_meshes.h"

namespace fq {
namespace {

using test::vertex;

// A noisy sphere and the same surface cut along a seam; the cut mesh's vertices are then
// shuffled, so that the welded frame's order is not the sphere's and the copies are not last.
struct Seam {
  Mesh whole, split;
  std::vector<uint32_t> original;  ///< per vertex of `split`: its vertex of `whole`
  double mean_edge = 0.0;
};

Seam noisy_sphere_with_seam(uint64_t seed = 3) {
  Seam s;
  s.whole = test::make_icosphere(4, 10.f);  // 2562 vertices
  add_gaussian_noise(s.whole, 0.25, seed);
  std::vector<uint32_t> original;
  const Mesh split = test::split_along_seam(s.whole, original);
  std::vector<uint32_t> place(split.num_vertices());
  std::iota(place.begin(), place.end(), 0u);
  std::shuffle(place.begin(), place.end(), std::mt19937(5));
  s.split.positions.resize(split.positions.size());
  s.original.resize(split.num_vertices());
  for (uint32_t v = 0; v < split.num_vertices(); ++v) {
    std::copy_n(&split.positions[3 * size_t(v)], 3, &s.split.positions[3 * size_t(place[v])]);
    s.original[place[v]] = original[v];
  }
  for (uint32_t c : split.triangles) s.split.triangles.push_back(place[c]);
  s.mean_edge = mean_edge_length(s.whole.view());
  return s;
}

FrameResult run(Engine& engine, const Mesh& mesh, const Params& p) {
  FrameResult out;
  const Status st = engine.process(mesh.view(), p, out);
  EXPECT_TRUE(st.ok()) << st.message();
  return out;
}

// Largest distance between two twins' results, in mean edges.
double twin_gap(const Seam& s, const std::vector<float>& positions) {
  std::vector<uint32_t> first(s.whole.num_vertices(), ~0u);
  double gap = 0.0;
  for (uint32_t v = 0; v < s.split.num_vertices(); ++v) {
    uint32_t& f = first[s.original[v]];
    if (f == ~0u) f = v;
    gap = std::max(gap, std::sqrt(double(norm2(vertex(positions, v) - vertex(positions, f)))));
  }
  return gap / s.mean_edge;
}

bool has_pass(const FrameResult& r, const std::string& name) {
  return std::any_of(r.timings.begin(), r.timings.end(), [&](const PassTiming& t) { return t.name == name; });
}

TEST(KernelSeamWeld, TwinsGetOneResultInTheInputsOrderAndCount) {
  const Seam s = noisy_sphere_with_seam();
  const uint32_t twins = s.split.num_vertices() - s.whole.num_vertices();
  ASSERT_GT(twins, 40u);
  CpuEngine engine(2);
  const FrameResult welded = run(engine, s.split, Params{});  // qf+, the default
  ASSERT_EQ(welded.positions.size(), s.split.positions.size());
  EXPECT_EQ(welded.welded_vertices, twins);
  EXPECT_TRUE(has_pass(welded, "weld"));
  EXPECT_LT(twin_gap(s, welded.positions), 1e-6);
  // Filtered apart, each copy sees one side's triangles only: the seam cracks.
  engine.set_weld_seams(false);
  const FrameResult apart = run(engine, s.split, Params{});
  EXPECT_EQ(apart.welded_vertices, 0u);
  EXPECT_GT(twin_gap(s, apart.positions), 0.05);
}

TEST(KernelSeamWeld, TheCutSurfaceFiltersAsTheWholeOne) {
  const Seam s = noisy_sphere_with_seam();
  CpuEngine engine(2);
  const FrameResult whole = run(engine, s.whole, Params{});
  const FrameResult split = run(engine, s.split, Params{});
  ASSERT_EQ(split.positions.size(), s.split.positions.size());
  EXPECT_EQ(split.mean_edge, whole.mean_edge);
  EXPECT_EQ(split.noise_estimate, whole.noise_estimate);
  double worst = 0.0;
  for (uint32_t v = 0; v < s.split.num_vertices(); ++v) {
    const Vec3 d = vertex(split.positions, v) - vertex(whole.positions, s.original[v]);
    worst = std::max(worst, std::sqrt(double(norm2(d))) / s.mean_edge);
  }
  // Only the order of the welded vertices differs; the engine's sums run in grid order, so the
  // results were equal bit for bit here, and the bound allows for float summation order.
  EXPECT_LT(worst, 1e-4);
}

// qf+ and clusters with their link forest; sigma_d 2 gives the sphere enough clusters.
Params filter_and_clusters() {
  Params p;
  p.cluster = true;
  p.clustering.sigma_d = 2.f;
  p.clustering.sigma_q = 1.f;
  p.clustering.keep_links = true;
  return p;
}

TEST(KernelSeamWeld, TwinsShareTheirClusterLabelAndLinks) {
  const Seam s = noisy_sphere_with_seam();
  const Params p = filter_and_clusters();
  Params labels_only = p;
  labels_only.filter = false;
  CpuEngine engine(2);
  for (const Params& q : {p, labels_only}) {
    SCOPED_TRACE(q.filter ? "filter and cluster" : "cluster only");
    const FrameResult r = run(engine, s.split, q);
    ASSERT_EQ(r.labels.size(), s.split.num_vertices());
    ASSERT_EQ(r.link_parent.size(), s.split.num_vertices());
    ASSERT_EQ(r.link_p.size(), s.split.num_vertices());
    EXPECT_GT(r.num_clusters, 1u);
    std::vector<uint32_t> label_of(s.whole.num_vertices(), ~0u);
    for (uint32_t v = 0; v < s.split.num_vertices(); ++v) {
      ASSERT_LT(r.labels[v], r.num_clusters);
      ASSERT_LT(r.link_parent[v], s.split.num_vertices());
      uint32_t& l = label_of[s.original[v]];
      if (l == ~0u) l = r.labels[v];
      ASSERT_EQ(r.labels[v], l) << "vertex " << v;
      // A link kept at the frame's theta joins two vertices of one cluster.
      if (r.link_p[v] >= 1.f - r.theta) {
        EXPECT_EQ(r.labels[r.link_parent[v]], r.labels[v]) << "vertex " << v;
      }
    }
    if (!q.filter) {
      EXPECT_EQ(r.positions, s.split.positions);  // the input itself
    }
  }
}

TEST(KernelSeamWeld, AMeshWithoutTwinsTakesThePathOfBeforeBitForBit) {
  const Seam s = noisy_sphere_with_seam();
  Params quadric;
  quadric.filtering.method = FilterMethod::kQuadric;
  CpuEngine welding(2), plain(2);
  plain.set_weld_seams(false);
  for (const Params& p : {Params{}, filter_and_clusters(), quadric}) {
    const FrameResult a = run(welding, s.whole, p), b = run(plain, s.whole, p);
    test::expect_identical(a, b, test::mode_name(p.filtering.method));
    EXPECT_EQ(a.link_p, b.link_p);
    EXPECT_EQ(a.welded_vertices, 0u);
    ASSERT_EQ(a.timings.size(), b.timings.size());
    for (size_t i = 0; i < a.timings.size(); ++i) EXPECT_EQ(a.timings[i].name, b.timings[i].name);
  }
}

TEST(KernelSeamWeld, AStreamKeepsItsHistoryAcrossFramesWithAndWithoutTwins) {
  CpuEngine engine(2);
  TemporalHistory history;
  engine.set_history(&history);
  Params p;
  p.filtering.temporal = 0.75f;
  for (int t = 0; t < 6; ++t) {
    const Seam s = noisy_sphere_with_seam(100 + t);
    const bool cut = t % 2 == 0;
    const FrameResult r = run(engine, cut ? s.split : s.whole, p);
    ASSERT_EQ(r.positions.size(), (cut ? s.split : s.whole).positions.size());
    if (cut) {
      EXPECT_LT(twin_gap(s, r.positions), 1e-6) << "frame " << t;
    }
    if (t > 0) {
      EXPECT_GT(r.prior_coverage, 0.9f) << "frame " << t;
      EXPECT_FALSE(r.history_reset) << "frame " << t;
    }
    // The history holds the welded frame: one vertex per point of the surface.
    EXPECT_EQ(history.positions.size(), s.whole.positions.size());
  }
  EXPECT_EQ(history.frames, 6u);
}

TEST(KernelSeamWeld, AFaultIsNamedInTheInputsNumbering) {
  Seam s = noisy_sphere_with_seam();
  const uint32_t n = s.split.num_vertices();
  s.split.triangles.back() = n + 5;
  CpuEngine engine(2);
  FrameResult out;
  const Status st = engine.process(s.split.view(), Params{}, out);
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.message().find("references vertex " + std::to_string(n + 5) + " but the mesh has " +
                              std::to_string(n) + " vertices"),
            std::string::npos)
      << st.message();
}

// Large enough for two slices of the search (kernels/seam_weld.cpp); the copies' z is -0, the
// same point as the originals' +0.
TEST(KernelSeamWeld, TheSearchIsTheSameOnAnyThreadCountAndSignedZerosAreOnePoint) {
  std::vector<uint32_t> original;
  Mesh m = test::split_along_seam(test::make_plane_grid(400, 400), original, 200.f);
  const uint32_t twins = m.num_vertices() - 401 * 401;
  ASSERT_EQ(twins, 401u);
  for (uint32_t v = 401 * 401; v < m.num_vertices(); ++v) m.positions[3 * size_t(v) + 2] = -0.f;
  SeamWeld one, two;
  EXPECT_EQ(one.find(m.view(), 1), twins);
  EXPECT_EQ(two.find(m.view(), 2), twins);
  const MeshView a = one.weld(m.view(), 1), b = two.weld(m.view(), 2);
  ASSERT_EQ(a.num_vertices, 401u * 401u);
  ASSERT_EQ(b.num_vertices, a.num_vertices);
  const std::vector<uint32_t> ta(a.triangles, a.triangles + 3 * size_t(a.num_triangles));
  // Each set of twins becomes its first copy: the welded frame is the grid the cut came from.
  EXPECT_EQ(ta, test::make_plane_grid(400, 400).triangles);
  EXPECT_TRUE(std::equal(ta.begin(), ta.end(), b.triangles));
  EXPECT_TRUE(std::equal(a.positions, a.positions + 3 * size_t(a.num_vertices), b.positions));
  // A grid one vertex apart has no twins.
  EXPECT_EQ(one.find(test::make_plane_grid(400, 400).view(), 2), 0u);
}

}  // namespace
}  // namespace fq
