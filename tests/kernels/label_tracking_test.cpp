// Stable cluster ids across frames (kernels/label_tracking.h) and the nearest-vertex
// matcher under it (kernels/nearest_vertex.h).
#include "kernels/label_tracking.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <random>
#include <set>

#include "eval/capture_sequence.h"
#include "eval/label_persistence.h"
#include "kernels/cpu_engine.h"
#include "kernels/frame_prep.h"
#include "kernels/nearest_vertex.h"
#include "tests/support/test_meshes.h"

namespace fq {
namespace {

TEST(KernelNearestVertex, MatchesBruteForce) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-5.f, 5.f);
  std::vector<float> pts(3 * 500), queries(3 * 200);
  for (float& x : pts) x = u(rng);
  for (float& x : queries) x = 1.5f * u(rng);  // some far outside the points' box
  NearestVertexIndex index;
  index.build(pts.data(), 500, 0.7f);
  std::vector<uint32_t> got;
  index.nearest_all(queries.data(), 200, 1e9f, got, 2);
  for (uint32_t q = 0; q < 200; ++q) {
    float best = 1e30f;
    for (uint32_t i = 0; i < 500; ++i) {
      float d2 = 0;
      for (int k = 0; k < 3; ++k)
        d2 += (pts[3 * i + k] - queries[3 * q + k]) * (pts[3 * i + k] - queries[3 * q + k]);
      best = std::min(best, d2);
    }
    ASSERT_NE(got[q], NearestVertexIndex::kNone);
    float d2 = 0;
    for (int k = 0; k < 3; ++k)
      d2 += (pts[3 * got[q] + k] - queries[3 * q + k]) * (pts[3 * got[q] + k] - queries[3 * q + k]);
    EXPECT_FLOAT_EQ(d2, best) << "query " << q;
  }
  EXPECT_EQ(index.nearest({100.f, 0.f, 0.f}, 1.f), NearestVertexIndex::kNone) << "beyond max_radius";
}

// The frame matcher gives the sparse index's answers, in the queries' own order: on a surface
// (its uniform grid) and with a far outlier that widens the grid's cells (its sparse index).
TEST(KernelFrameMatcher, GivesTheNearestVertexIndexAnswers) {
  std::mt19937 rng(5);
  std::normal_distribution<float> jitter(0.f, 0.05f);
  std::uniform_real_distribution<float> angle(0.f, 6.2831853f), height(-1.f, 1.f);
  std::vector<float> pts, queries;
  for (int i = 0; i < 3000; ++i) {  // points on a unit sphere, queries near it
    const float z = height(rng), a = angle(rng), r = std::sqrt(1.f - z * z);
    for (float c : {r * std::cos(a), r * std::sin(a), z}) pts.push_back(c);
  }
  for (int i = 0; i < 2000; ++i) {
    const float z = height(rng), a = angle(rng), r = std::sqrt(1.f - z * z);
    for (float c : {r * std::cos(a), r * std::sin(a), z}) queries.push_back(c + jitter(rng));
  }
  for (const bool outlier : {false, true}) {
    std::vector<float> p = pts;
    if (outlier) p.insert(p.end(), {1e6f, 0.f, 0.f});
    const uint32_t n = uint32_t(p.size() / 3), q = uint32_t(queries.size() / 3);
    NearestVertexIndex index;
    FrameMatcher matcher, asked;
    index.build(p.data(), n, 0.06f);
    matcher.build(p.data(), n, 0.06f);
    asked.build(queries.data(), q, 0.06f);
    EXPECT_EQ(matcher.sparse(), outlier);
    for (float reach : {0.02f, 0.5f}) {
      std::vector<uint32_t> want, got;
      index.nearest_all(queries.data(), q, reach, want, 2);
      matcher.nearest_all(asked, reach, got, 2);
      EXPECT_EQ(got, want) << "outlier " << outlier << " reach " << reach;
      const auto none = std::count(got.begin(), got.end(), FrameMatcher::kNone);
      if (reach < 0.05f)
        EXPECT_GT(none, 0) << "some queries have nothing within a short reach";
      else
        EXPECT_EQ(none, 0);
    }
  }
}

// A surface whose bounds hold more than 8 cells of the wanted size a point: the grid's cell
// grows three of its steps (1.26^3 = 2.0004 times), not an outlier's widening, so the matcher
// keeps its grid, with the sparse index's answers, also to queries asked with a reach wider
// than the index's (kMaxReachCells cells: a next frame of a much longer mean edge).
TEST(KernelFrameMatcher, KeepsTheGridWhereTheCellGrewThreeSteps) {
  std::mt19937 rng(7);
  std::normal_distribution<float> g(0.f, 1.f), jitter(0.f, 0.01f);
  std::vector<float> pts, queries;
  for (int i = 0; i < 3000; ++i) {  // a unit sphere, cells of 0.04: 51^3 cells wanted, 24,000 allowed
    const Vec3 p = normalized_or_zero({g(rng), g(rng), g(rng)});
    pts.insert(pts.end(), {p.x, p.y, p.z});
    queries.insert(queries.end(), {p.x + jitter(rng), p.y + jitter(rng), p.z + jitter(rng)});
  }
  FrameMatcher matcher, asked;
  matcher.build(pts.data(), 3000, 0.04f);
  asked.build(queries.data(), 3000, 0.04f);
  EXPECT_FALSE(matcher.sparse());
  NearestVertexIndex index;
  index.build(pts.data(), 3000, 0.04f);
  std::vector<uint32_t> want, got;
  index.nearest_all(queries.data(), 3000, 0.32f, want, 2);
  matcher.nearest_all(asked, 0.32f, got, 2);
  EXPECT_EQ(got, want);
  std::vector<float> outside = queries;
  for (size_t i = 0; i < outside.size(); ++i)
    outside[i] *= 1.f + 0.5f * float(i / 3 % 2);  // every other point 0.5 out
  FrameMatcher asked_outside;
  asked_outside.build(outside.data(), 3000, 0.04f);
  index.nearest_all(outside.data(), 3000, 2.f, want, 2);
  matcher.nearest_all(asked_outside, 2.f, got, 2);
  EXPECT_EQ(got, want);
  EXPECT_GT(std::count(got.begin(), got.end(), FrameMatcher::kNone), 500) << "the far half finds nothing";
}

// The same surface as a new capture: vertices shuffled, jittered, clusters renumbered.
struct Frame {
  std::vector<float> positions;
  std::vector<uint32_t> labels;
};

Frame recaptured(const Frame& f, uint32_t k, uint32_t seed, std::vector<uint32_t>& source_of) {
  const uint32_t n = uint32_t(f.labels.size());
  std::mt19937 rng(seed);
  source_of.resize(n);
  std::iota(source_of.begin(), source_of.end(), 0u);
  std::shuffle(source_of.begin(), source_of.end(), rng);
  std::vector<uint32_t> rename(k);
  std::iota(rename.begin(), rename.end(), 0u);
  std::shuffle(rename.begin(), rename.end(), rng);
  std::normal_distribution<float> jitter(0.f, 1e-3f);
  Frame out;
  for (uint32_t v = 0; v < n; ++v) {
    for (int c = 0; c < 3; ++c) out.positions.push_back(f.positions[3 * source_of[v] + c] + jitter(rng));
    out.labels.push_back(rename[f.labels[source_of[v]]]);
  }
  return out;
}

TEST(KernelLabelTracking, PermutedJitteredCopyGetsTheSameIds) {
  const Mesh sphere = test::make_icosphere(3);
  Frame a{sphere.positions, {}};
  const uint32_t k = 7;
  for (uint32_t v = 0; v < sphere.num_vertices(); ++v)
    a.labels.push_back(uint32_t((sphere.positions[3 * v] + 1.f) * 3.49f));
  LabelTracker tracker;
  TrackingOptions o;
  o.cell = 0.1f;
  std::vector<uint32_t> first = a.labels;
  EXPECT_EQ(tracker.track(a.positions.data(), sphere.num_vertices(), first, k, o), k);
  EXPECT_EQ(first, a.labels) << "the first frame keeps its labels";
  std::vector<uint32_t> source_of;
  Frame b = recaptured(a, k, 11, source_of);
  EXPECT_EQ(tracker.track(b.positions.data(), sphere.num_vertices(), b.labels, k, o), k);
  for (uint32_t v = 0; v < b.labels.size(); ++v)
    ASSERT_EQ(b.labels[v], a.labels[source_of[v]]) << "vertex " << v;
}

// Frames that made the matcher quadratic: one vertex a million units away (the grid's cell
// grew until the whole surface sat in a few cells), and every vertex on one of four points.
// Ids must still follow the vertices; the times are printed (speed is judged by fqtrackbench
// and this output, not asserted).
double tracked_pair_ms(const Frame& a, const Frame& b, uint32_t k, float cell, std::vector<uint32_t>& ids) {
  LabelTracker tracker;
  TrackingOptions o;
  o.cell = cell;
  o.max_distance = 8.f * cell;
  o.threads = 2;
  std::vector<uint32_t> first = a.labels;
  const uint32_t n = uint32_t(a.labels.size());
  tracker.track(a.positions.data(), n, first, k, o);
  ids = b.labels;
  const auto t0 = std::chrono::steady_clock::now();
  tracker.track(b.positions.data(), n, ids, k, o);
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

TEST(KernelLabelTracking, AnOutlierOrACollapsedFrameIsMatchedWithoutAQuadraticSearch) {
  const Mesh sphere = test::make_icosphere(7);  // 163,842 vertices
  const uint32_t n = sphere.num_vertices(), k = 7;
  Frame a{sphere.positions, {}};
  for (uint32_t v = 0; v < n; ++v)
    a.labels.push_back(uint32_t((sphere.positions[3 * size_t(v)] + 1.f) * 3.49f));
  a.positions[0] = 1e6f;  // the outlier
  Mesh with_outlier = sphere;
  with_outlier.positions = a.positions;
  const float cell = float(mean_edge_length(with_outlier.view()));
  std::vector<uint32_t> source_of, ids;
  const Frame b = recaptured(a, k, 5, source_of);
  const double outlier_ms = tracked_pair_ms(a, b, k, cell, ids);
  uint32_t same = 0;
  for (uint32_t v = 0; v < n; ++v) same += ids[v] == a.labels[source_of[v]] ? 1u : 0u;
  EXPECT_GE(same, n - 1) << "every vertex but the outlier keeps its id";

  Frame c{std::vector<float>(3 * size_t(n)), std::vector<uint32_t>(n)};
  for (uint32_t v = 0; v < n; ++v) {
    c.labels[v] = v % 4;
    c.positions[3 * v + c.labels[v] % 3] =
        float(c.labels[v]);  // four points: (0,0,0) (1,0,0) (0,2,0) (0,0,3)
  }
  const Frame d = recaptured(c, 4, 6, source_of);
  const double collapsed_ms = tracked_pair_ms(c, d, 4, 0.5f, ids);
  same = 0;
  for (uint32_t v = 0; v < n; ++v) same += ids[v] == c.labels[source_of[v]] ? 1u : 0u;
  EXPECT_EQ(same, n) << "each of the four points keeps its id";
  std::printf("tracking 163,842 vertices: one outlier %.0f ms, four points %.0f ms\n", outlier_ms,
              collapsed_ms);
}

TEST(KernelLabelTracking, AnExpiredTokenLeavesTheFrameAndTheTrackerAsTheyWere) {
  const Mesh sphere = test::make_icosphere(3);
  const uint32_t k = 7;
  Frame a{sphere.positions, {}};
  for (uint32_t v = 0; v < sphere.num_vertices(); ++v)
    a.labels.push_back(uint32_t((sphere.positions[3 * size_t(v)] + 1.f) * 3.49f));
  LabelTracker tracker;
  TrackingOptions o;
  o.cell = 0.1f;
  std::vector<uint32_t> first = a.labels;
  tracker.track(a.positions.data(), sphere.num_vertices(), first, k, o);
  std::vector<uint32_t> source_of;
  const Frame b = recaptured(a, k, 11, source_of);
  std::atomic<bool> stop{true};
  std::vector<uint32_t> ids = b.labels;
  uint32_t bound = 99;
  const Status s =
      tracker.track_until(CancelToken(&stop), b.positions.data(), sphere.num_vertices(), ids, k, o, bound);
  EXPECT_EQ(s.code(), StatusCode::kCancelled);
  EXPECT_EQ(ids, b.labels) << "the engine's numbering, untouched";
  EXPECT_EQ(bound, 99u);
  // The next frame is matched with the first one, as if the stopped one had never come.
  stop = false;
  ASSERT_TRUE(
      tracker.track_until(CancelToken(&stop), b.positions.data(), sphere.num_vertices(), ids, k, o, bound)
          .ok());
  for (uint32_t v = 0; v < ids.size(); ++v) ASSERT_EQ(ids[v], a.labels[source_of[v]]) << "vertex " << v;
}

// The tracker keeps its buffers from frame to frame: a restart must forget everything the last
// frames left in them, and a frame of another size must be matched like any other.
TEST(KernelLabelTracking, ARestartOrAFrameOfAnotherSizeIsTrackedAsByAFreshTracker) {
  const Mesh big = test::make_icosphere(4), small = test::make_icosphere(2);
  const uint32_t k = 7;
  auto striped = [&](const Mesh& m) {
    Frame f{m.positions, {}};
    for (uint32_t v = 0; v < m.num_vertices(); ++v)
      f.labels.push_back(uint32_t((m.positions[3 * size_t(v)] + 1.f) * 3.49f));
    return f;
  };
  std::vector<uint32_t> source_of;
  const Frame a0 = striped(big), s0 = striped(small);
  const Frame a1 = recaptured(a0, k, 21, source_of), s1 = recaptured(s0, k, 22, source_of);
  TrackingOptions o;
  o.cell = 0.05f;
  o.max_distance = 0.4f;
  auto track = [&](LabelTracker& t, const Frame& f, uint32_t clusters, uint32_t* bound = nullptr) {
    std::vector<uint32_t> ids = f.labels;
    const uint32_t b = t.track(f.positions.data(), uint32_t(f.labels.size()), ids, clusters, o);
    if (bound != nullptr) *bound = b;
    return ids;
  };
  LabelTracker fresh, reused;
  const std::vector<uint32_t> want_a0 = track(fresh, a0, k), want_a1 = track(fresh, a1, k);
  fresh.reset();
  const std::vector<uint32_t> want_s0 = track(fresh, s0, k), want_s1 = track(fresh, s1, k);
  for (int round = 0; round < 2; ++round) {
    EXPECT_EQ(track(reused, a0, k), want_a0);
    EXPECT_EQ(track(reused, a1, k), want_a1);
    reused.reset();
    EXPECT_EQ(track(reused, s0, k), want_s0) << "round " << round;
    EXPECT_EQ(track(reused, s1, k), want_s1) << "round " << round;
    reused.reset();
  }
  // Without a restart, the small frame then the big one: with a vote over one frame a frame's
  // ids follow from the last frame's alone, so a fresh tracker given the small frame's ids agrees.
  o.vote_frames = 1;
  LabelTracker growing, from_small;
  uint32_t bound = 0;
  track(growing, a0, k);
  track(growing, a1, k);
  Frame tracked_s0 = s0;
  tracked_s0.labels = track(growing, s0, k, &bound);
  track(from_small, tracked_s0, bound);
  EXPECT_EQ(track(growing, a1, k), track(from_small, a1, k));
}

// 21 x 21 grid: previous frame = left half id 0, right half id 1.
TEST(KernelLabelTracking, SplitClusterKeepsItsIdOnTheLargerPart) {
  const Mesh grid = test::make_plane_grid(20, 20);
  auto x_of = [](uint32_t v) { return int(v % 21); };
  std::vector<uint32_t> prev(grid.num_vertices());
  for (uint32_t v = 0; v < prev.size(); ++v) prev[v] = x_of(v) <= 10 ? 0u : 1u;
  LabelTracker tracker;
  TrackingOptions o;
  o.vote_frames = 1;  // the matching alone (the vote waits a frame before a split shows)
  tracker.track(grid.positions.data(), grid.num_vertices(), prev, 2, o);
  // New frame, numbered afresh: the left half splits into x <= 3 (small) and 4..10 (large).
  std::vector<uint32_t> cur(grid.num_vertices());
  for (uint32_t v = 0; v < cur.size(); ++v) cur[v] = x_of(v) <= 3 ? 2u : (x_of(v) <= 10 ? 1u : 0u);
  const uint32_t bound = tracker.track(grid.positions.data(), grid.num_vertices(), cur, 3, o);
  std::set<uint32_t> small;
  for (uint32_t v = 0; v < cur.size(); ++v) {
    if (x_of(v) > 10)
      ASSERT_EQ(cur[v], 1u);
    else if (x_of(v) >= 4)
      ASSERT_EQ(cur[v], 0u) << "the larger part keeps the id";
    else
      small.insert(cur[v]);
  }
  ASSERT_EQ(small.size(), 1u);
  EXPECT_GT(*small.begin(), 1u) << "the smaller part gets an id the previous frame did not use";
  EXPECT_EQ(bound, *small.begin() + 1);
}

TEST(KernelLabelTracking, NewRegionAndMergedClusters) {
  // Previous ids 0..3 by votes; cluster 0 overlaps ids 2 (5 votes) and 3 (3 votes): merged,
  // it keeps 2; cluster 1 overlaps nothing (a new region) and must not reuse 0, 1 or 3.
  const std::vector<uint32_t> labels = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 2, 2};
  const uint32_t none = NearestVertexIndex::kNone;
  const std::vector<uint32_t> votes = {2, 2, 2, 2, 2, 3, 3, 3, none, none, 0, 0};
  const std::vector<bool> prev_used = {true, true, true, true};
  const std::vector<uint32_t> id = match_cluster_ids(labels, 3, votes, prev_used);
  EXPECT_EQ(id[0], 2u);
  EXPECT_EQ(id[2], 0u);
  EXPECT_EQ(id[1], 4u);
}

// 21 x 21 grid: column 10 flips to the right cluster for one frame (noise), then for good.
TEST(KernelLabelTracking, VoteOutvotesOneFrameFlipsAndFollowsLastingChanges) {
  const Mesh grid = test::make_plane_grid(20, 20);
  const uint32_t n = grid.num_vertices();
  auto frame = [&](int last_left_column) {
    std::vector<uint32_t> l(n);
    for (uint32_t v = 0; v < n; ++v) l[v] = int(v % 21) <= last_left_column ? 1u : 0u;  // numbered afresh
    return l;
  };
  auto column_10 = [&](const std::vector<uint32_t>& l) {
    std::set<uint32_t> ids;
    for (uint32_t v = 10; v < n; v += 21) ids.insert(l[v]);
    return ids;
  };
  LabelTracker tracker;
  TrackingOptions o;
  ASSERT_EQ(o.vote_frames, 3);
  // Raw sides of column 10 per frame: left, right (noise), left, left, right, right (a real change).
  std::vector<std::vector<uint32_t>> f = {frame(10), frame(9), frame(10), frame(10), frame(9), frame(9)};
  tracker.track(grid.positions.data(), n, f[0], 2, o);
  const uint32_t left = f[0][0], right = f[0][20];
  for (size_t t = 1; t < f.size(); ++t) tracker.track(grid.positions.data(), n, f[t], 2, o);
  EXPECT_EQ(column_10(f[1]), std::set<uint32_t>{left})
      << "a one-frame flip is outvoted (tie: the previous id)";
  EXPECT_EQ(column_10(f[2]), std::set<uint32_t>{left});
  EXPECT_EQ(column_10(f[4]), std::set<uint32_t>{left}) << "window right, left, left";
  EXPECT_EQ(column_10(f[5]), std::set<uint32_t>{right}) << "two frames of three: the change holds";
  EXPECT_EQ(f[5][9], left);
  EXPECT_EQ(f[5][11], right);
  // Without the vote the flip shows at once.
  LabelTracker plain;
  o.vote_frames = 1;
  std::vector<uint32_t> g0 = frame(10), g1 = frame(9);
  plain.track(grid.positions.data(), n, g0, 2, o);
  plain.track(grid.positions.data(), n, g1, 2, o);
  EXPECT_EQ(column_10(g1), std::set<uint32_t>{g0[20]});
}

// End to end through the engine: shuffled, re-noised captures of a cube clustered
// independently; tracked ids persist far better than the engine's own numbering, and sticky
// borders or the default vote over frames better than ids alone.
double mean_persistence(int rings, int vote_frames, bool tracked) {
  const Mesh clean = test::make_cube(10);
  Params p;
  p.filter = false;
  p.cluster = true;
  p.clustering.sigma_d = 3.f;
  p.clustering.target_clusters = 6;
  CpuEngine engine(2);
  LabelTracker tracker;
  TrackingOptions o;
  o.cell = 0.2f;
  o.sticky_rings = rings;
  o.vote_frames = vote_frames;
  Mesh prev;
  std::vector<uint32_t> prev_ids;
  double sum = 0;
  const int frames = 6;
  for (int t = 0; t < frames; ++t) {
    const Mesh m = capture_frame(clean, 0.0, 0.05, 60 + t);
    FrameResult r;
    EXPECT_TRUE(engine.process(m.view(), p, r).ok());
    std::vector<uint32_t> ids = r.labels;
    o.triangles = m.triangles.data();
    o.num_triangles = m.num_triangles();
    if (tracked) tracker.track(m.positions.data(), m.num_vertices(), ids, r.num_clusters, o);
    if (t > 0)
      sum += label_persistence(prev.positions.data(), prev_ids.data(), prev.num_vertices(),
                               m.positions.data(), ids.data(), m.num_vertices(), o.cell);
    prev = m;
    prev_ids = ids;
  }
  return sum / (frames - 1);
}

TEST(KernelLabelTracking, EngineLabelsPersistAcrossCaptures) {
  const double raw = mean_persistence(0, 1, false);
  const double ids_only = mean_persistence(0, 1, true);
  const double sticky = mean_persistence(2, 1, true);
  const TrackingOptions defaults;
  const double voted = mean_persistence(defaults.sticky_rings, defaults.vote_frames, true);
  EXPECT_GT(ids_only, raw);
  EXPECT_GE(sticky, ids_only);
  EXPECT_GE(sticky, 0.9);
  EXPECT_GT(voted, ids_only);
  EXPECT_GE(voted, 0.9) << "the defaults";
  RecordProperty("persistence", std::to_string(raw) + " " + std::to_string(ids_only) + " " +
                                    std::to_string(sticky) + " " + std::to_string(voted));
}

}  // namespace
}  // namespace fq
