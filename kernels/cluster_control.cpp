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
    if (count < target) lo = best_t + 1; else hi = best_t;
    std::vector<uint32_t> trial;
    while (lo < hi && count != target) {
      const uint32_t mid = lo + (hi - lo) / 2;
      const uint32_t k = labels_for(mid, trial);
      if (gap(k) < gap(count) || (gap(k) == gap(count) && mid < best_t)) {
        best_t = mid;
        count = k;
        labels.swap(trial);
      }
      if (k < target) lo = mid + 1; else hi = mid;
    }
    return ladder.cut(best_t);
  }
};

void append_timings(const char* prefix, const FrameResult& from, FrameResult& to) {
  for (const PassTiming& t : from.timings) to.timings.push_back({std::string(prefix) + t.name, t.ms});
}

/// The filter that makes the clustering geometry: normal-constrained, because the
/// unconstrained minimizer slides vertices onto creases, where both sides explain them.
Params geometry_filter(const Params& plain) {
  Params g = plain;
  g.filter = true;
  g.cluster = false;
  g.filtering.constrained = true;
  // The labels' geometry leaves the stream's history to the output's filter (one update a frame).
  g.filtering.temporal = 0.f;
  return g;
}

/// On the denoised mesh the quadrics can be sharper: half the filter's spatial and range
/// extents (measured on noisy fandisk, docs/QUALITY.md).
Params clustering_pass(const Params& plain) {
  Params c = plain;
  c.filter = false;
  c.cluster = true;
  c.filtering.sigma_s *= 0.5f;
  c.filtering.sigma_r *= 0.5f;
  c.filtering.sigma_b *= 0.5f;  // 0 (the default) stays the default, sigma_s / 2
  c.filtering.sigma_n *= 0.5f;
  return c;
}

bool same_filter(const Params& a, const Params& b) {
  const FilterParams &x = a.filtering, &y = b.filtering;
  return x.method == y.method && x.sigma_s == y.sigma_s && x.sigma_r == y.sigma_r && x.sigma_b == y.sigma_b &&
         x.sigma_n == y.sigma_n && x.constrained == y.constrained && x.tikhonov == y.tikhonov;
}

/// Clusters the filtered geometry: the user's filter (when filtering) for the output, the
/// geometry filter (the same run when they agree), then the clustering pass on its result.
Status cluster_filtered(Engine& engine, ClusterRuns& runs, const MeshView& mesh, const Params& plain,
                        FrameResult& out) {
  const Params geometry = geometry_filter(plain);
  const FrameResult* shape = &out;
  if (plain.filter) {
    Params user = plain;
    user.cluster = false;
    if (Status s = engine.process(mesh, user, out); !s.ok()) return s;
  }
  if (!plain.filter || !same_filter(plain, geometry)) {
    if (Status s = engine.process(mesh, geometry, runs.geometry); !s.ok()) return s;
    if (plain.filter) {
      append_timings("geometry.", runs.geometry, out);
    } else {
      out.timings = runs.geometry.timings;
      out.mean_edge = runs.geometry.mean_edge;
      out.positions.assign(mesh.positions, mesh.positions + 3 * size_t(mesh.num_vertices));
    }
    shape = &runs.geometry;
  }
  MeshView filtered = mesh;
  filtered.positions = shape->positions.data();
  FrameResult& c = runs.clusters;
  if (Status s = engine.process(filtered, clustering_pass(plain), c); !s.ok()) return s;
  append_timings("cluster.", c, out);
  out.labels.swap(c.labels);
  out.link_parent.swap(c.link_parent);
  out.link_p.swap(c.link_p);
  out.num_clusters = c.num_clusters;
  out.theta = c.theta;
  return {};
}

}  // namespace

bool needs_cluster_control(const Params& p) {
  const ClusterParams& c = p.cluster ? p.clustering : ClusterParams{};
  return c.target_clusters > 0 || c.effective_geometry() == ClusterGeometry::kFiltered || c.min_cluster_size > 0;
}

Status process_with_cluster_control(Engine& engine, const MeshView& mesh, const Params& p, FrameResult& out) {
  if (Status s = validate(p); !s.ok()) return s;
  Params plain = p;
  plain.clustering.target_clusters = 0;
  plain.clustering.min_cluster_size = 0;
  plain.clustering.geometry = ClusterGeometry::kInput;
  const bool on_filtered = p.clustering.effective_geometry() == ClusterGeometry::kFiltered;
  if (p.clustering.target_clusters > 0) {
    plain.clustering.theta = 1.0f;  // cut nothing: the forest gives every other theta
    plain.clustering.keep_links = true;
  }
  const Status s =
      on_filtered ? cluster_filtered(engine, engine.cluster_runs_, mesh, plain, out) : engine.process(mesh, plain, out);
  if (!s.ok()) return s;
  const auto t0 = std::chrono::steady_clock::now();
  if (p.clustering.target_clusters > 0) {
    const TargetSearch search{mesh, {out.link_parent.data(), out.link_p.data(), mesh.num_vertices}, p.clustering};
    out.theta = theta_for_cut(search.run(out.labels, out.num_clusters));
  } else if (p.clustering.min_cluster_size > 0) {
    out.num_clusters = connect_clusters(mesh, out.labels, p.clustering.min_cluster_size);
  }
  if (!p.clustering.keep_links) {
    out.link_parent.clear();
    out.link_p.clear();
  }
  out.timings.push_back(
      {"cluster_control", std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count()});
  return {};
}

}  // namespace fq
