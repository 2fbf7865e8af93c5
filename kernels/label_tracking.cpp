#include "kernels/label_tracking.h"

#include <algorithm>
#include <tuple>

namespace fq {

namespace {

constexpr uint32_t kNone = NearestVertexIndex::kNone;

struct Overlap {
  uint32_t count, cluster, prev_id;
};

/// Every (cluster, previous id) pair with its vertex count: counting sort by cluster, then
/// a sort of each cluster's votes.
std::vector<Overlap> overlaps(const std::vector<uint32_t>& labels, uint32_t k, const std::vector<uint32_t>& votes) {
  std::vector<uint32_t> start(k + 1, 0);
  for (uint32_t l : labels) ++start[l + 1];
  for (uint32_t c = 0; c < k; ++c) start[c + 1] += start[c];
  std::vector<uint32_t> by_cluster(labels.size()), cursor(start.begin(), start.end() - 1);
  for (size_t v = 0; v < labels.size(); ++v) by_cluster[cursor[labels[v]]++] = votes[v];
  std::vector<Overlap> out;
  for (uint32_t c = 0; c < k; ++c) {
    auto b = by_cluster.begin() + start[c], e = by_cluster.begin() + start[c + 1];
    std::sort(b, e);
    for (auto it = b; it != e;) {
      auto run_end = std::upper_bound(it, e, *it);
      if (*it != kNone) out.push_back({uint32_t(run_end - it), c, *it});
      it = run_end;
    }
  }
  return out;
}

/// Vertices whose previous id is the label of a neighbour across a border take that id.
void stick_to_previous_side(const TrackingOptions& o, const std::vector<uint32_t>& votes,
                            std::vector<uint32_t>& labels) {
  std::vector<uint32_t> to(labels.size(), kNone);
  auto offer = [&](uint32_t a, uint32_t b) {
    if (votes[a] != kNone && votes[a] != labels[a] && labels[b] == votes[a]) to[a] = votes[a];
  };
  for (uint32_t t = 0; t < o.num_triangles; ++t) {
    const uint32_t* v = o.triangles + 3 * size_t(t);
    for (int k = 0; k < 3; ++k) {
      offer(v[k], v[(k + 1) % 3]);
      offer(v[(k + 1) % 3], v[k]);
    }
  }
  for (size_t v = 0; v < labels.size(); ++v) {
    if (to[v] != kNone) labels[v] = to[v];
  }
}

/// The majority vote over time (see the header). `history` receives, per vertex, this
/// frame's id then the history of its nearest previous vertex (`window` entries); `votes`
/// are the previous frame's ids (the tie-break); `labels` become the most frequent id.
void vote_over_frames(const std::vector<uint32_t>& nearest, const std::vector<uint32_t>& prev_history, int prev_window,
                      int window, const std::vector<uint32_t>& votes, std::vector<uint32_t>& history,
                      std::vector<uint32_t>& labels) {
  const size_t n = labels.size();
  history.assign(n * size_t(window), kNone);
  for (size_t v = 0; v < n; ++v) {
    uint32_t* h = &history[v * window];
    h[0] = labels[v];
    if (nearest[v] != kNone) {
      const uint32_t* p = &prev_history[size_t(nearest[v]) * prev_window];
      for (int k = 1; k < window && k <= prev_window; ++k) h[k] = p[k - 1];
    }
    uint32_t best = h[0];
    int best_count = 0;
    for (int a = 0; a < window; ++a) {
      if (h[a] == kNone) continue;
      int count = 0;
      for (int b = 0; b < window; ++b) count += h[b] == h[a] ? 1 : 0;
      if (count > best_count || (count == best_count && h[a] == votes[v])) {
        best = h[a];
        best_count = count;
      }
    }
    labels[v] = best;
  }
}

}  // namespace

std::vector<uint32_t> match_cluster_ids(const std::vector<uint32_t>& labels, uint32_t k,
                                        const std::vector<uint32_t>& votes, const std::vector<bool>& prev_used) {
  std::vector<Overlap> pairs = overlaps(labels, k, votes);
  // Largest overlaps first; ties by cluster then id, so the result is reproducible.
  std::sort(pairs.begin(), pairs.end(), [](const Overlap& a, const Overlap& b) {
    return std::tie(b.count, a.cluster, a.prev_id) < std::tie(a.count, b.cluster, b.prev_id);
  });
  std::vector<uint32_t> id(k, kNone);
  std::vector<bool> taken(prev_used.size(), false);
  for (const Overlap& o : pairs) {
    if (id[o.cluster] != kNone || o.prev_id >= taken.size() || taken[o.prev_id]) continue;
    id[o.cluster] = o.prev_id;
    taken[o.prev_id] = true;
  }
  // New regions: the lowest ids neither the previous frame nor this one uses.
  uint32_t next = 0;
  for (uint32_t c = 0; c < k; ++c) {
    if (id[c] != kNone) continue;
    while (next < prev_used.size() && (prev_used[next] || taken[next])) ++next;
    id[c] = next++;
  }
  return id;
}

uint32_t LabelTracker::track(const float* positions, uint32_t n, std::vector<uint32_t>& labels,
                             uint32_t num_clusters, const TrackingOptions& o) {
  uint32_t bound = num_clusters;
  const Status s = track_until(CancelToken{}, positions, n, labels, num_clusters, o, bound);
  (void)s;  // a token that never expires: always ok
  return bound;
}

Status LabelTracker::track_until(const CancelToken& token, const float* positions, uint32_t n,
                                 std::vector<uint32_t>& labels, uint32_t num_clusters, const TrackingOptions& o,
                                 uint32_t& bound) {
  const CancelScope scope(&token);
  // Everything is computed aside and kept only once the whole frame is tracked.
  std::vector<uint32_t> ids = labels;
  std::vector<uint32_t> history;
  int window = 1;
  uint32_t new_bound = num_clusters;
  // This frame's matcher first: the next frame is matched against it, and this frame's
  // queries go to the previous one in its cell order (FrameMatcher::nearest_all).
  FrameMatcher index;
  index.build(positions, n, o.cell);
  FQ_RETURN_IF_ERROR(token.check());
  if (has_previous()) {
    std::vector<uint32_t> nearest, votes(n);
    prev_.nearest_all(index, o.max_distance, nearest, o.threads);
    FQ_RETURN_IF_ERROR(token.check());
    for (uint32_t v = 0; v < n; ++v) votes[v] = nearest[v] == kNone ? kNone : prev_ids_[nearest[v]];
    // Ids still in a vertex's vote window count as used: a new cluster must not take one.
    std::vector<bool> prev_used(prev_bound_, false);
    for (uint32_t id : prev_ids_) prev_used[id] = true;
    for (uint32_t id : prev_history_) {
      if (id != kNone) prev_used[id] = true;
    }
    const std::vector<uint32_t> id = match_cluster_ids(ids, num_clusters, votes, prev_used);
    for (uint32_t& l : ids) l = id[l];
    if (o.triangles) {
      for (int ring = 0; ring < o.sticky_rings; ++ring) {
        FQ_RETURN_IF_ERROR(token.check());
        stick_to_previous_side(o, votes, ids);
      }
    }
    window = std::max(o.vote_frames, 1);
    vote_over_frames(nearest, prev_history_, prev_window_, window, votes, history, ids);
    new_bound = 0;
    for (uint32_t l : ids) new_bound = std::max(new_bound, l + 1);
    for (uint32_t l : history) {
      if (l != kNone) new_bound = std::max(new_bound, l + 1);
    }
  } else {
    history = ids;
  }
  prev_ = std::move(index);
  prev_history_.swap(history);
  prev_window_ = window;
  prev_ids_ = ids;
  prev_bound_ = new_bound;
  labels.swap(ids);
  bound = new_bound;
  return {};
}

void LabelTracker::reset() {
  prev_.clear();
  prev_ids_.clear();
  prev_history_.clear();
  prev_window_ = 0;
  prev_bound_ = 0;
}

}  // namespace fq
