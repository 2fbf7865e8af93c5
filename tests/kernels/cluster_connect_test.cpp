// Connected clusters (kernels/cluster_connect.h): every label one edge-connected piece,
// small pieces merged into a neighbour.
#include "kernels/cluster_connect.h"

#include <gtest/gtest.h>

#include <map>
#include <numeric>
#include <vector>

#include "tests/support/test_meshes.h"

namespace fq {
namespace {

// Number of edge-connected pieces of each label, by flood fill.
std::map<uint32_t, int> pieces_per_label(const Mesh& m, const std::vector<uint32_t>& labels) {
  const uint32_t n = m.num_vertices();
  std::vector<std::vector<uint32_t>> adj(n);
  for (size_t t = 0; t < m.triangles.size(); t += 3)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = m.triangles[t + k], b = m.triangles[t + (k + 1) % 3];
      adj[a].push_back(b);
      adj[b].push_back(a);
    }
  std::vector<bool> seen(n, false);
  std::map<uint32_t, int> pieces;
  for (uint32_t s = 0; s < n; ++s) {
    if (seen[s]) continue;
    ++pieces[labels[s]];
    std::vector<uint32_t> stack{s};
    seen[s] = true;
    while (!stack.empty()) {
      const uint32_t v = stack.back();
      stack.pop_back();
      for (uint32_t w : adj[v])
        if (!seen[w] && labels[w] == labels[v]) seen[w] = true, stack.push_back(w);
    }
  }
  return pieces;
}

// 20 x 20 grid: label 0 on the left and right thirds (two pieces), 1 in the middle.
std::vector<uint32_t> split_label(const Mesh& grid, int n) {
  std::vector<uint32_t> labels(grid.num_vertices());
  for (uint32_t v = 0; v < labels.size(); ++v) {
    const int x = int(v % (n + 1));
    labels[v] = (x < n / 3 || x > 2 * n / 3) ? 0u : 1u;
  }
  return labels;
}

TEST(KernelClusterConnect, SplitsALabelIntoItsPieces) {
  const int n = 20;
  const Mesh grid = test::make_plane_grid(n, n);
  std::vector<uint32_t> labels = split_label(grid, n);
  ASSERT_EQ(pieces_per_label(grid, labels)[0], 2);
  EXPECT_EQ(connect_clusters(grid.view(), labels, 0), 3u);
  for (const auto& [label, count] : pieces_per_label(grid, labels)) EXPECT_EQ(count, 1) << label;
}

TEST(KernelClusterConnect, MergesSmallPiecesIntoANeighbour) {
  const int n = 20;
  const Mesh grid = test::make_plane_grid(n, n);
  std::vector<uint32_t> labels(grid.num_vertices(), 0);
  // Speckle: isolated single vertices with labels of their own, as noise gives.
  for (uint32_t v = 50; v < labels.size(); v += 97) labels[v] = 1 + v;
  const uint32_t k = connect_clusters(grid.view(), labels, 5);
  EXPECT_EQ(k, 1u);
  for (uint32_t l : labels) EXPECT_EQ(l, 0u);
}

TEST(KernelClusterConnect, EveryLabelConnectedAndLargeEnough) {
  const int n = 24;
  const Mesh grid = test::make_plane_grid(n, n);
  std::vector<uint32_t> labels(grid.num_vertices());
  for (uint32_t v = 0; v < labels.size(); ++v) labels[v] = (v * 2654435761u >> 7) % 9;  // scattered labels
  const uint32_t min_size = 12;
  const uint32_t k = connect_clusters(grid.view(), labels, min_size);
  std::vector<uint32_t> size(k, 0);
  for (uint32_t l : labels) {
    ASSERT_LT(l, k);
    ++size[l];
  }
  for (uint32_t s : size) EXPECT_GE(s, min_size);
  for (const auto& [label, count] : pieces_per_label(grid, labels)) EXPECT_EQ(count, 1) << label;
  EXPECT_EQ(std::accumulate(size.begin(), size.end(), 0u), grid.num_vertices());
}

}  // namespace
}  // namespace fq
