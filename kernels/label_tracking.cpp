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
/// each cluster's votes counted in an array over the previous ids (in no particular order:
/// match_cluster_ids sorts the pairs by a total order).
std::vector<Overlap> overlaps(const std::vector<uint32_t>& labels, uint32_t k,
                              const std::vector<uint32_t>& votes) {
  std::vector<uint32_t> start(k + 1, 0);
  for (uint32_t l : labels) ++start[l + 1];
  for (uint32_t c = 0; c < k; ++c) start[c + 1] += start[c];
  uint32_t id_bound = 0;
  for (uint32_t id : votes) id_bound = id != kNone ? std::max(id_bound, id + 1) : id_bound;
  std::vector<uint32_t> by_cluster(labels.size()), cursor(start.begin(), start.end() - 1);
  for (size_t v = 0; v < labels.size(); ++v) by_cluster[cursor[labels[v]]++] = votes[v];
  std::vector<uint32_t> count(id_bound, 0), seen;
  std::vector<Overlap> out;
  for (uint32_t c = 0; c < k; ++c) {
    for (uint32_t i = start[c]; i < start[c + 1]; ++i) {
      const uint32_t id = by_cluster[i];
      if (id == kNone) continue;
      if (count[id]++ == 0) seen.push_back(id);
    }
    for (uint32_t id : seen) {
      out.push_back({count[id], c, id});
      count[id] = 0;
    }
    seen.clear();
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

/// The majority vote over time (see the header), in this frame's cell order (k-th vertex:
/// `frame.original(k)`), with the previous frame's histories in its cell order (`nearest`: per
/// vertex, the position there of its nearest previous vertex). `history` receives, per vertex,
/// this frame's id then its nearest previous vertex's history (`window` entries), and
/// `sorted_ids` its final id, both in cell order; `votes` are the previous frame's ids (the
/// tie-break); `labels` become the most frequent id, one of the vertex's history. Returns the
/// bound of the ids in `history` (so of `labels` too), and sets `used` (that long) where an id
/// is in it; every id is below `id_limit`.
uint32_t vote_over_frames(const FrameMatcher& frame, const std::vector<uint32_t>& nearest,
                          const std::vector<uint32_t>& prev_history, int prev_window, int window,
                          const std::vector<uint32_t>& votes, uint32_t id_limit,
                          std::vector<uint32_t>& history, std::vector<uint32_t>& sorted_ids,
                          std::vector<uint32_t>& labels, std::vector<bool>& used) {
  const uint32_t n = frame.size();
  history.resize(size_t(n) * window);
  sorted_ids.resize(n);
  used.assign(id_limit, false);
  uint32_t bound = 0;
  for (uint32_t k = 0; k < n; ++k) {
    const uint32_t v = frame.original(k);
    uint32_t* h = &history[size_t(k) * window];
    h[0] = labels[v];
    const uint32_t* p = nearest[k] == kNone ? nullptr : &prev_history[size_t(nearest[k]) * prev_window];
    for (int i = 1; i < window; ++i) h[i] = p != nullptr && i <= prev_window ? p[i - 1] : kNone;
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
      bound = std::max(bound, h[a] + 1);
      used[h[a]] = true;
    }
    labels[v] = best;
    sorted_ids[k] = best;
  }
  used.resize(bound);
  return bound;
}

}  // namespace

std::vector<uint32_t> match_cluster_ids(const std::vector<uint32_t>& labels, uint32_t k,
                                        const std::vector<uint32_t>& votes,
                                        const std::vector<bool>& prev_used) {
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
                                 std::vector<uint32_t>& labels, uint32_t num_clusters,
                                 const TrackingOptions& o, uint32_t& bound) {
  const CancelScope scope(&token);
  // Everything is computed aside (in buffers kept from frame to frame) and kept only once the
  // whole frame is tracked. This frame's matcher first: the next frame is matched against it,
  // and this frame's queries go to the previous one in its cell order.
  next_.build(positions, n, o.cell);
  FQ_RETURN_IF_ERROR(token.check());
  ids_.assign(labels.begin(), labels.end());
  int window = 1;
  uint32_t new_bound = num_clusters;
  if (has_previous()) {
    // Lookups, previous ids and histories in cell order: neighbouring vertices read
    // neighbouring entries of the previous frame's.
    prev_.nearest_all_in_cell_order(next_, o.max_distance, nearest_, o.threads);
    FQ_RETURN_IF_ERROR(token.check());
    votes_.resize(n);
    for (uint32_t k = 0; k < n; ++k)
      votes_[next_.original(k)] = nearest_[k] == kNone ? kNone : prev_ids_[nearest_[k]];
    // prev_used_: the ids still in a vertex's vote window; a new cluster must not take one.
    const std::vector<uint32_t> id = match_cluster_ids(ids_, num_clusters, votes_, prev_used_);
    for (uint32_t& l : ids_) l = id[l];
    if (o.triangles) {
      for (int ring = 0; ring < o.sticky_rings; ++ring) {
        FQ_RETURN_IF_ERROR(token.check());
        stick_to_previous_side(o, votes_, ids_);
      }
    }
    window = std::max(o.vote_frames, 1);
    // Ids in the previous histories are below prev_bound_, new ones below prev_bound_ + num_clusters.
    const uint32_t id_limit = prev_bound_ + num_clusters;
    new_bound = vote_over_frames(next_, nearest_, prev_history_, prev_window_, window, votes_, id_limit,
                                 history_, sorted_ids_, ids_, used_);
  } else {
    sorted_ids_.resize(n);
    for (uint32_t k = 0; k < n; ++k) sorted_ids_[k] = ids_[next_.original(k)];
    history_ = sorted_ids_;
    used_.assign(num_clusters, false);
    for (uint32_t id : ids_) used_[id] = true;
  }
  std::swap(prev_, next_);
  prev_history_.swap(history_);
  prev_window_ = window;
  prev_ids_.swap(sorted_ids_);
  prev_used_.swap(used_);
  prev_bound_ = new_bound;
  std::copy(ids_.begin(), ids_.end(), labels.begin());
  bound = new_bound;
  return {};
}

void LabelTracker::reset() { *this = LabelTracker(); }

}  // namespace fq
