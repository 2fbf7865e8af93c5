// The uniform grid and its neighbour visitor (kernels/grid.h, grid_build.h) against brute
// force: for every query the visitor must report exactly the points within the radius,
// each once; no missing and no extra neighbours, whatever the cloud, radius or query.
#include "kernels/grid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>
#include <vector>

#include "kernels/grid_build.h"

namespace fq {
namespace {

using Cloud = std::vector<Vec3>;

// A built grid over a cloud, with the sorted points the visitor reads.
struct BuiltGrid {
  CpuGrid grid;
  std::vector<Point4> sorted;
  GridView view() const { return grid.view(sorted.data()); }
};

BuiltGrid build(const Cloud& cloud, float cell) {
  BuiltGrid b;
  build_grid(cloud.data(), uint32_t(cloud.size()), cell, b.grid);
  b.sorted.resize(cloud.size());
  for (size_t k = 0; k < cloud.size(); ++k) {
    const Vec3 p = cloud[b.grid.order[k]];
    b.sorted[k] = {p.x, p.y, p.z, float(k)};
  }
  return b;
}

// Original indices within `radius` of q, computed exactly as the visitor does.
std::vector<uint32_t> brute_force(const Cloud& cloud, Vec3 q, float radius) {
  const float r2 = radius * radius;
  std::vector<uint32_t> out;
  for (uint32_t i = 0; i < cloud.size(); ++i) {
    const Vec3 d{cloud[i].x - q.x, cloud[i].y - q.y, cloud[i].z - q.z};
    if (norm2(d) <= r2) out.push_back(i);
  }
  return out;
}

std::vector<uint32_t> visited(const BuiltGrid& b, Vec3 q, float radius) {
  std::vector<uint32_t> out;
  for_each_neighbor(b.view(), q, radius, [&](uint32_t j, const Point4& pj, Vec3 d, float d2) {
    EXPECT_EQ(pj.w, float(j)) << "point handed over is not points[j]";
    EXPECT_EQ(d.x, pj.x - q.x);
    EXPECT_EQ(d2, norm2(d));
    out.push_back(b.grid.order[j]);
  });
  std::sort(out.begin(), out.end());
  return out;
}

// Queries: every cloud point, random points in the bounds grown by `margin` on each side
// (so many lie outside the grid) and a few far away.
Cloud queries_for(const Cloud& cloud, float margin, uint32_t seed) {
  Vec3 lo, hi;
  bounds_of(cloud.data(), uint32_t(cloud.size()), lo, hi);
  std::mt19937 rng(seed);
  Cloud q = cloud;
  std::uniform_real_distribution<float> ux(lo.x - margin, hi.x + margin), uy(lo.y - margin, hi.y + margin),
      uz(lo.z - margin, hi.z + margin);
  for (int k = 0; k < 300; ++k) q.push_back({ux(rng), uy(rng), uz(rng)});
  q.push_back({hi.x + 1e3f, hi.y, hi.z});
  q.push_back({lo.x - 1e3f, lo.y - 1e3f, lo.z - 1e3f});
  return q;
}

void expect_matches_brute_force(const Cloud& cloud, float cell, float radius, const std::string& what) {
  SCOPED_TRACE(what + " cell=" + std::to_string(cell) + " radius=" + std::to_string(radius));
  const BuiltGrid b = build(cloud, cell);
  size_t total = 0;
  for (const Vec3& q : queries_for(cloud, 2.f * radius + 1.f, 5)) {
    const std::vector<uint32_t> want = brute_force(cloud, q, radius), got = visited(b, q, radius);
    ASSERT_EQ(got, want) << "query (" << q.x << ", " << q.y << ", " << q.z << ")";
    total += got.size();
  }
  // Guard against a vacuous pass: the queries must find something (except empty clouds).
  if (!cloud.empty()) {
    EXPECT_GT(total, cloud.size() / 2);
  }
}

Cloud uniform_cloud(uint32_t n, float extent, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.f, extent);
  Cloud c(n);
  for (Vec3& p : c) p = {u(rng), u(rng), u(rng)};
  return c;
}

// Tight blobs far apart: most cells are empty.
Cloud clustered_cloud(uint32_t n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> centre(-20.f, 20.f);
  std::normal_distribution<float> g(0.f, 0.4f);
  Cloud centres(5);
  for (Vec3& c : centres) c = {centre(rng), centre(rng), centre(rng)};
  Cloud c(n);
  for (uint32_t i = 0; i < n; ++i) c[i] = centres[i % 5] + Vec3{g(rng), g(rng), g(rng)};
  return c;
}

TEST(KernelGrid, UniformCloudsMatchBruteForce) {
  for (uint32_t seed : {1u, 2u, 3u}) {
    const Cloud c = uniform_cloud(1500, 10.f, seed);
    for (float radius : {0.3f, 1.f, 2.5f})
      expect_matches_brute_force(c, 1.f, radius, "uniform seed " + std::to_string(seed));
  }
}

TEST(KernelGrid, ClusteredCloudsWithEmptyRegionsMatchBruteForce) {
  for (uint32_t seed : {11u, 12u, 13u}) {
    const Cloud c = clustered_cloud(1500, seed);
    for (float radius : {0.2f, 0.7f, 3.f})
      expect_matches_brute_force(c, 0.7f, radius, "clustered seed " + std::to_string(seed));
  }
}

TEST(KernelGrid, RadiusMuchLargerAndSmallerThanTheCell) {
  const Cloud c = uniform_cloud(800, 6.f, 21);
  expect_matches_brute_force(c, 0.25f, 2.f, "radius 8 cells");
  expect_matches_brute_force(c, 3.f, 0.4f, "radius 0.13 cell");
}

TEST(KernelGrid, FlatCloudMatchesBruteForce) {
  Cloud c = uniform_cloud(1000, 8.f, 31);
  for (Vec3& p : c) p.z = 0.f;  // a plane: one layer of cells
  expect_matches_brute_force(c, 1.f, 1.f, "flat");
}

TEST(KernelGrid, DuplicatePointsAreEachReported) {
  Cloud c = uniform_cloud(200, 5.f, 41);
  const Cloud once = c;
  for (int copy = 0; copy < 2; ++copy) c.insert(c.end(), once.begin(), once.end());
  expect_matches_brute_force(c, 1.f, 0.8f, "triplicated");
  expect_matches_brute_force(c, 1.f, 0.f, "radius zero finds exact duplicates");
  const Cloud same(50, Vec3{1.f, 2.f, 3.f});  // zero extent on every axis
  expect_matches_brute_force(same, 1.f, 0.5f, "all coincident");
}

TEST(KernelGrid, TinyClouds) {
  expect_matches_brute_force(Cloud{{0.5f, -1.f, 2.f}}, 1.f, 1.f, "one point");
  const BuiltGrid empty = build(Cloud{}, 1.f);
  EXPECT_TRUE(visited(empty, {0, 0, 0}, 10.f).empty());
}

TEST(KernelGrid, GridIsACountingSortByCell) {
  const Cloud c = clustered_cloud(2000, 51);
  const BuiltGrid b = build(c, 0.5f);
  const GridView g = b.view();
  ASSERT_EQ(b.grid.cell_start.size(), b.grid.layout.cells() + 1);
  EXPECT_EQ(b.grid.cell_start.back(), c.size());
  std::vector<uint32_t> perm = b.grid.order;
  std::sort(perm.begin(), perm.end());
  for (uint32_t i = 0; i < perm.size(); ++i) ASSERT_EQ(perm[i], i);
  for (uint64_t cell = 0; cell < b.grid.layout.cells(); ++cell) {
    for (uint32_t k = b.grid.cell_start[cell]; k < b.grid.cell_start[cell + 1]; ++k) {
      ASSERT_EQ(cell_index(g, c[b.grid.order[k]]), cell);
      if (k > b.grid.cell_start[cell]) {
        ASSERT_LT(b.grid.order[k - 1], b.grid.order[k]) << "not stable";
      }
    }
  }
}

TEST(KernelGridLayout, CellGrowsOnAHugeBoxWithFewPoints) {
  const GridLayout l = choose_grid_layout({0, 0, 0}, {1e4f, 1e4f, 1e4f}, 1.f, 10);
  EXPECT_LE(l.cells(), 4096u);
  EXPECT_GT(l.cell, 1.f);
  EXPECT_GE(l.nx * double(l.cell), 1e4);  // the cells still cover the box
  EXPECT_GE(l.nz * double(l.cell), 1e4);
  // Bigger n allows more cells (8 per point) but never beyond that.
  const GridLayout l2 = choose_grid_layout({0, 0, 0}, {1e4f, 1e4f, 1e4f}, 1.f, 100000);
  EXPECT_LE(l2.cells(), 800000u);
  EXPECT_LT(l2.cell, l.cell);
  // A wanted cell of zero must not loop forever nor allocate without bound.
  const GridLayout l3 = choose_grid_layout({0, 0, 0}, {1, 1, 1}, 0.f, 100);
  EXPECT_LE(l3.cells(), 4096u);
  EXPECT_GT(l3.cell, 0.f);
}

TEST(KernelGridLayout, GrownCellStillMatchesBruteForce) {
  Cloud c = uniform_cloud(10, 1e4f, 61);
  c.push_back({0, 0, 0});
  c.push_back({1e4f, 1e4f, 1e4f});
  for (float radius : {1.f, 500.f, 5000.f}) expect_matches_brute_force(c, 1.f, radius, "grown cell");
  const BuiltGrid b = build(c, 1.f);
  EXPECT_GT(b.grid.layout.cell, 100.f);
}

}  // namespace
}  // namespace fq
