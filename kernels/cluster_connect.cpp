#include "kernels/cluster_connect.h"

#include <algorithm>
#include <numeric>
#include <unordered_map>

namespace fq {

namespace {

class DisjointSets {
 public:
  explicit DisjointSets(uint32_t n) : up_(n) { std::iota(up_.begin(), up_.end(), 0u); }
  uint32_t find(uint32_t x) {
    while (up_[x] != x) x = up_[x] = up_[up_[x]];
    return x;
  }
  /// Joins the sets; the smaller index stays the representative (deterministic numbering).
  void join(uint32_t a, uint32_t b) {
    a = find(a), b = find(b);
    if (a != b) up_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<uint32_t> up_;
};

template <class Fn>
void for_each_edge(const MeshView& m, Fn&& fn) {
  for (uint32_t t = 0; t < m.num_triangles; ++t) {
    const uint32_t* v = m.triangles + 3 * size_t(t);
    fn(v[0], v[1]);
    fn(v[1], v[2]);
    fn(v[2], v[0]);
  }
}

/// One round of merging: every part under min_size goes into the neighbouring part it
/// shares most edges with (ties: the larger, then the lower index). False when nothing merged.
bool merge_small_parts(const MeshView& m, DisjointSets& parts, std::vector<uint32_t>& size,
                       uint32_t min_size) {
  std::unordered_map<uint64_t, uint32_t> shared;  // (small part, neighbour part) -> edge count
  for_each_edge(m, [&](uint32_t a, uint32_t b) {
    const uint32_t pa = parts.find(a), pb = parts.find(b);
    if (pa == pb) return;
    if (size[pa] < min_size) ++shared[(uint64_t(pa) << 32) | pb];
    if (size[pb] < min_size) ++shared[(uint64_t(pb) << 32) | pa];
  });
  std::unordered_map<uint32_t, std::pair<uint32_t, uint32_t>> best;  // small -> (neighbour, edges)
  for (const auto& [key, count] : shared) {
    const uint32_t small = uint32_t(key >> 32), nb = uint32_t(key);
    auto it = best.find(small);
    if (it == best.end()) {
      best[small] = {nb, count};
      continue;
    }
    auto& [cur, cur_count] = it->second;
    const bool better = count != cur_count      ? count > cur_count
                        : size[nb] != size[cur] ? size[nb] > size[cur]
                                                : nb < cur;
    if (better) it->second = {nb, count};
  }
  // Smallest parts first, so that a part absorbs its tiny neighbours before it is judged.
  std::vector<uint32_t> order;
  for (const auto& [small, choice] : best) order.push_back(small);
  std::sort(order.begin(), order.end(),
            [&](uint32_t a, uint32_t b) { return size[a] != size[b] ? size[a] < size[b] : a < b; });
  bool merged = false;
  for (uint32_t small : order) {
    const uint32_t a = parts.find(small), b = parts.find(best[small].first);
    if (a == b || size[a] >= min_size) continue;
    const uint32_t total = size[a] + size[b];
    parts.join(a, b);
    size[parts.find(a)] = total;
    merged = true;
  }
  return merged;
}

}  // namespace

uint32_t connect_clusters(const MeshView& m, std::vector<uint32_t>& labels, uint32_t min_size) {
  const uint32_t n = m.num_vertices;
  DisjointSets parts(n);
  for_each_edge(m, [&](uint32_t a, uint32_t b) {
    if (labels[a] == labels[b]) parts.join(a, b);
  });
  std::vector<uint32_t> size(n, 0);
  for (uint32_t v = 0; v < n; ++v) ++size[parts.find(v)];
  // Two small parts may merge into each other and still be small: repeat until nothing merges.
  for (int round = 0; round < 32 && min_size > 1 && merge_small_parts(m, parts, size, min_size); ++round) {
  }
  std::vector<uint32_t> id(n, UINT32_MAX);
  uint32_t k = 0;
  for (uint32_t v = 0; v < n; ++v) {
    const uint32_t r = parts.find(v);
    if (id[r] == UINT32_MAX) id[r] = k++;
    labels[v] = id[r];
  }
  return k;
}

}  // namespace fq
