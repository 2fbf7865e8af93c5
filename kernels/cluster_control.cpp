#include "kernels/cluster_control.h"

#include <algorithm>
#include <chrono>
#include <string>

#include "kernels/cluster_connect.h"
#include "kernels/cluster_forest.h"

namespace fq {

namespace {

// Labels for a target count. Without the connectivity step the count is exactly
// roots + cut links, so the ladder gives the cut at once; with it, splits and merges move
// the count a little, and a bisection over the ladder (count is close to monotone in the
// number of cut links) finds the closest achieved count.
struct TargetSearch {
  const MeshView& mesh;
  const LinkForest forest;
  const ClusterParams& c;
  CutLadder ladder{forest};

  uint32_t labels_for(uint32_t t, std::vector<uint32_t>& labels) const {
    const uint32_t k = labels_at_cut(forest, ladder.cut(t), labels);
    return c.min_cluster_size > 0 ? connect_clusters(mesh, labels, c.min_cluster_size) : k;
  }

  /// Returns the chosen cut; `labels` and `count` its result.
  float run(std::vector<uint32_t>& labels, uint32_t& count) const {
    const uint32_t target = c.target_clusters;
    uint32_t best_t = ladder.t_for(target);
    count = labels_for(best_t, labels);
    if (c.min_cluster_size == 0) return ladder.cut(best_t);
    auto gap = [&](uint32_t k) { return k > target ? k - target : target - k; };
    uint32_t lo = 0, hi = ladder.links();
    if (count < target)
      lo = best_t + 1;
    else
      hi = best_t;
    std::vector<uint32_t> trial;
    while (lo < hi && count != target) {
      const uint32_t mid = lo + (hi - lo) / 2;
      const uint32_t k = labels_for(mid, trial);
      if (gap(k) < gap(count) || (gap(k) == gap(count) && mid < best_t)) {
        best_t = mid;
        count = k;
        labels.swap(trial);
      }
      if (k < target)
        lo = mid + 1;
      else
        hi = mid;
    }
    return ladder.cut(best_t);
  }
};

}  // namespace

bool needs_cluster_control(const Params& p) {
  const ClusterParams& c = p.cluster ? p.clustering : ClusterParams{};
  return c.target_clusters > 0 || c.effective_geometry() == ClusterGeometry::kFiltered ||
         c.min_cluster_size > 0;
}

void finish_cluster_control(const MeshView& mesh, const ClusterParams& asked, FrameResult& out) {
  const auto t0 = std::chrono::steady_clock::now();
  if (asked.target_clusters > 0) {
    const TargetSearch search{mesh, {out.link_parent.data(), out.link_p.data(), mesh.num_vertices}, asked};
    out.theta = theta_for_cut(search.run(out.labels, out.num_clusters));
  } else if (asked.min_cluster_size > 0) {
    out.num_clusters = connect_clusters(mesh, out.labels, asked.min_cluster_size);
  }
  if (!asked.keep_links) {
    out.link_parent.clear();
    out.link_p.clear();
  }
  out.timings.push_back(
      {"cluster_control",
       std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count()});
}

}  // namespace fq
