// The CUDA engine's match to a stream's last result (kernels/grid_nearest.h), run here on the
// host: on a grid laid out over other bounds than the points' (the new frame's), its answers
// are the brute-force nearest within reach and the CPU engine's NearestVertexIndex's, for
// points and queries inside the layout, outside it and far away; and the host's box walk of the
// same spheres (kernels/box_nearest.h), which must give its answer for every query.
#include "kernels/grid_nearest.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "kernels/box_nearest.h"
#include "kernels/grid_build.h"

namespace fq {
namespace {

// A grid of `points` in `layout` (they need not lie in it), sorted as the device sorts them:
// by cell, then by index.
struct LaidOutGrid {
  std::vector<uint32_t> cell_start, order;
  std::vector<Point4> sorted;
  GridView view;
};

LaidOutGrid lay_out(const std::vector<Vec3>& points, const GridLayout& layout) {
  LaidOutGrid g;
  const auto n = static_cast<uint32_t>(points.size());
  GridView shape{layout.origin, layout.cell, layout.nx, layout.ny, layout.nz, nullptr, nullptr, n};
  g.cell_start.assign(layout.cells() + 1, 0);
  std::vector<uint32_t> cell_of(n);
  for (uint32_t i = 0; i < n; ++i) {
    cell_of[i] = cell_index(shape, points[i]);
    ++g.cell_start[cell_of[i] + 1];
  }
  for (size_t c = 0; c < layout.cells(); ++c) g.cell_start[c + 1] += g.cell_start[c];
  std::vector<uint32_t> cursor(g.cell_start.begin(), g.cell_start.end() - 1);
  g.order.resize(n);
  for (uint32_t i = 0; i < n; ++i) g.order[cursor[cell_of[i]]++] = i;
  for (uint32_t k = 0; k < n; ++k) {
    const Vec3 p = points[g.order[k]];
    g.sorted.push_back({p.x, p.y, p.z, 0.f});
  }
  g.view = shape;
  g.view.cell_start = g.cell_start.data();
  g.view.points = g.sorted.data();
  return g;
}

// Points on a unit-ish sphere about 0.1 apart, jittered: a surface sampled at its mean edge.
std::vector<Vec3> sphere_points(uint32_t n, float radius, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> g(0.f, 1.f);
  std::vector<Vec3> out(n);
  for (Vec3& p : out) p = radius * normalized_or_zero({g(rng), g(rng), g(rng)});
  return out;
}

uint32_t brute_force(const std::vector<Vec3>& points, Vec3 q, float reach) {
  uint32_t best = kNoNearest;
  float best_d2 = reach * reach;
  for (uint32_t i = 0; i < points.size(); ++i) {
    const float d2 = norm2(points[i] - q);
    if (d2 <= best_d2 && (best == kNoNearest || d2 < best_d2)) {
      best = i;
      best_d2 = d2;
    }
  }
  return best;
}

TEST(KernelGridNearest, MatchesBruteForceAndTheHostIndexWherePointsLieOutsideTheLayout) {
  // The last frame: a sphere of radius 10 (in mean edges, about 1 apart); the new frame's
  // layout covers only the middle of it, so a third of the points are clamped into its edge cells.
  const std::vector<Vec3> points = sphere_points(1200, 10.f, 1);
  const GridLayout layout =
      choose_grid_layout({-6.f, -6.f, -6.f}, {6.f, 6.f, 6.f}, 1.f, uint32_t(points.size()));
  const LaidOutGrid grid = lay_out(points, layout);
  std::vector<float> flat;
  for (const Vec3& p : points) flat.insert(flat.end(), {p.x, p.y, p.z});
  NearestVertexIndex index;
  index.build(flat.data(), uint32_t(points.size()), 1.f);

  std::mt19937 rng(2);
  std::normal_distribution<float> jitter(0.f, 0.7f);
  std::vector<Vec3> queries;
  for (const Vec3& p : sphere_points(600, 10.f, 3))
    queries.push_back(p + Vec3{jitter(rng), jitter(rng), jitter(rng)});
  queries.push_back({30.f, 0.f, 0.f});     // outside the layout, nothing within reach
  queries.push_back({0.f, 0.f, 0.f});      // inside, nothing within reach
  queries.push_back({1e30f, 1e30f, 0.f});  // far beyond any cell
  const float reach = 3.f;
  int outside = 0, found = 0;
  for (const Vec3& q : queries) {
    const uint32_t j = nearest_in_grid(grid.view, q, reach, 0.5f);
    const uint32_t got = j == kNoNearest ? kNoNearest : grid.order[j];
    const uint32_t want = brute_force(points, q, reach);
    ASSERT_EQ(got, want) << "query (" << q.x << ", " << q.y << ", " << q.z << ")";
    EXPECT_EQ(got, index.nearest(q, reach)) << "the host index answers the same";
    outside += std::abs(q.x) > 6.f || std::abs(q.y) > 6.f || std::abs(q.z) > 6.f;
    found += got != kNoNearest;
  }
  EXPECT_GT(outside, 100) << "many queries lie outside the layout";
  EXPECT_GT(found, 550);
  EXPECT_EQ(nearest_in_grid(grid.view, {std::nanf(""), 0.f, 0.f}, reach, 0.5f), kNoNearest);
}

TEST(KernelGridNearest, TiesGoToTheFirstInCellOrder) {
  // Two points at the same distance from the query, in one cell: the lower index wins, as in
  // NearestVertexIndex.
  const std::vector<Vec3> points = {{0.5f, 0.25f, 0.5f}, {0.5f, 0.75f, 0.5f}, {5.f, 5.f, 5.f}};
  const LaidOutGrid grid = lay_out(points, choose_grid_layout({0.f, 0.f, 0.f}, {6.f, 6.f, 6.f}, 1.f, 3));
  const uint32_t j = nearest_in_grid(grid.view, {0.5f, 0.5f, 0.5f}, 3.f, 0.5f);
  ASSERT_NE(j, kNoNearest);
  EXPECT_EQ(grid.order[j], 0u);
}

TEST(KernelGridNearest, AnEmptyGridOrNoReachFindsNothing) {
  const GridView empty{};
  EXPECT_EQ(nearest_in_grid(empty, {0.f, 0.f, 0.f}, 3.f, 0.5f), kNoNearest);
  const std::vector<Vec3> points = {{1.f, 1.f, 1.f}};
  const LaidOutGrid grid = lay_out(points, choose_grid_layout({0.f, 0.f, 0.f}, {2.f, 2.f, 2.f}, 1.f, 1));
  EXPECT_EQ(nearest_in_grid(grid.view, {1.5f, 1.f, 1.f}, 0.4f, 0.5f), kNoNearest) << "beyond reach";
  EXPECT_EQ(nearest_in_grid(grid.view, {1.5f, 1.f, 1.f}, 0.6f, 0.f), 0u)
      << "a first radius of 0 starts at reach";
}

// nearest_in_grid_boxes against nearest_in_grid, query by query, with the reaches and first
// radii given; returns how many queries found a point.
int expect_boxes_agree(const LaidOutGrid& grid, const std::vector<Vec3>& queries, float first_radius,
                       const std::vector<float>& reaches) {
  int found = 0;
  for (const float reach : reaches) {
    for (const Vec3& q : queries) {
      const uint32_t want = nearest_in_grid(grid.view, q, reach, first_radius);
      EXPECT_EQ(nearest_in_grid_boxes(grid.view, q, reach, first_radius), want)
          << "query (" << q.x << ", " << q.y << ", " << q.z << ") reach " << reach;
      found += want != kNoNearest;
    }
  }
  return found;
}

TEST(KernelGridNearestBoxes, GivesTheSpheresAnswersOnASurfaceAndOutsideTheLayout) {
  const std::vector<Vec3> points = sphere_points(1200, 10.f, 1);
  const LaidOutGrid grid =
      lay_out(points, choose_grid_layout({-6.f, -6.f, -6.f}, {6.f, 6.f, 6.f}, 1.f, 1200));
  std::mt19937 rng(4);
  std::normal_distribution<float> jitter(0.f, 0.7f);
  std::vector<Vec3> queries;
  for (const Vec3& p : sphere_points(800, 10.f, 5))
    queries.push_back(p + Vec3{jitter(rng), jitter(rng), jitter(rng)});
  queries.push_back({30.f, 0.f, 0.f});
  queries.push_back({0.f, 0.f, 0.f});
  queries.push_back({1e30f, 1e30f, 0.f});
  queries.push_back({std::nanf(""), 0.f, 0.f});
  const int found = expect_boxes_agree(grid, queries, 0.5f, {0.f, 0.3f, 3.f, 8.f, 1e30f, INFINITY});
  EXPECT_GT(found, 2000) << "most queries find a point within the longer reaches";
  EXPECT_EQ(nearest_in_grid_boxes(GridView{}, {0.f, 0.f, 0.f}, 3.f, 0.5f), kNoNearest);
}

TEST(KernelGridNearestBoxes, GivesTheSpheresAnswersOnTiesAndWhereTheBudgetRunsOut) {
  // A lattice on the cell bounds, asked at the centres of its cells and squares (up to 8
  // points at one distance: the first in cell order wins) ...
  std::vector<Vec3> points;
  for (int z = 0; z < 6; ++z) {
    for (int y = 0; y < 6; ++y) {
      for (int x = 0; x < 6; ++x) points.push_back({float(x), float(y), float(z)});
    }
  }
  std::vector<Vec3> queries;
  for (float z = 0.f; z < 6.f; z += 0.5f) {
    for (float y = 0.f; y < 6.f; y += 0.5f) {
      for (float x = 0.f; x < 6.f; x += 0.5f) queries.push_back({x, y, z});
    }
  }
  const LaidOutGrid lattice = lay_out(points, choose_grid_layout({0.f, 0.f, 0.f}, {5.f, 5.f, 5.f}, 1.f, 216));
  EXPECT_GT(expect_boxes_agree(lattice, queries, 0.5f, {0.4f, 0.9f, 3.f}), 3000);
  // ... and 2,000 points piled on four spots, more than the budget nearest_in_grid looks at.
  std::vector<Vec3> piles;
  for (uint32_t i = 0; i < 2000; ++i) piles.push_back({float(i % 4) * 0.7f, 1.f + 1e-4f * float(i % 7), 1.f});
  piles.push_back({3.f, 3.f, 3.f});
  const LaidOutGrid crowded =
      lay_out(piles, choose_grid_layout({0.f, 0.f, 0.f}, {4.f, 4.f, 4.f}, 0.5f, 2001));
  std::vector<Vec3> near_piles(40);
  for (int i = 0; i < 40; ++i) near_piles[i] = {0.1f * float(i), 1.2f, 1.1f + 0.05f * float(i % 5)};
  expect_boxes_agree(crowded, near_piles, 0.25f, {0.2f, 1.f, 4.f});
}

}  // namespace
}  // namespace fq
