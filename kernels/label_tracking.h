// Stable cluster ids across the frames of a stream. Quick shift numbers clusters by the
// input index of their root, which means nothing from one capture frame to the next (the
// vertices themselves differ). The tracker keeps the previous frame's vertices and ids;
// each new vertex votes for the id of the nearest previous vertex, each new cluster is
// matched to the previous ids it overlaps most (greedy, largest overlaps first), and
// clusters that overlap nothing left get ids the previous frame did not use. With the mesh's
// triangles, boundaries are also sticky: a vertex on the border between its cluster and the
// one that holds its previous id goes back to that one. Both sides of a border are equally
// right for such a vertex (on a crease, or where two clusters of a flat region meet), and
// without this rule noise flips them from frame to frame. Last, every vertex takes the id
// it was given most often over the last `vote_frames` frames (its own history follows its
// nearest previous vertex; a tie goes to the previous frame's id): a vertex the clustering
// puts on either side at random keeps the side it was on most, while a vertex that really
// changed cluster follows within about half the window.
#pragma once

#include <cstdint>
#include <vector>

#include "common/status.h"
#include "core/cancel_token.h"
#include "kernels/frame_matcher.h"

namespace fq {

struct TrackingOptions {
  float cell = 1.f;          ///< grid cell of the matcher, in input units (the mean edge)
  float max_distance = 8.f;  ///< a new vertex farther than this from every previous one votes for nothing
  int threads = 1;
  const uint32_t* triangles = nullptr;  ///< the frame's triangles: sticky boundaries; null: ids only
  uint32_t num_triangles = 0;
  int sticky_rings = 0;  ///< how deep (in edge rings) a border may move back to where it was
  int vote_frames = 3;   ///< frames of the per-vertex majority vote (1: off)
};

/// Ids for this frame's clusters from overlap votes. `labels`: this frame's clusters
/// (0..k-1); `votes`: per vertex the previous id it overlaps (kNone: none); `prev_used`:
/// the previous frame's ids (true where used). Returns the new id of each cluster.
std::vector<uint32_t> match_cluster_ids(const std::vector<uint32_t>& labels, uint32_t k,
                                        const std::vector<uint32_t>& votes,
                                        const std::vector<bool>& prev_used);

class LabelTracker {
 public:
  /// Replaces `labels` (one per vertex, each < num_clusters) by ids consistent with the
  /// previous call's frame, remembers this frame, and returns the id bound (every id is
  /// below it; ids of clusters that vanished stay unused, so it may exceed num_clusters).
  /// The first frame keeps its labels.
  uint32_t track(const float* positions, uint32_t n, std::vector<uint32_t>& labels, uint32_t num_clusters,
                 const TrackingOptions& options);
  /// track() under `token` (its parallel loops stop at their next chunk once it expires):
  /// kCancelled when it expired before the frame was tracked, and then `labels`, `bound` and
  /// the remembered frame are as they were, so the next frame is matched with the last one
  /// tracked. Every step is O(n log n) or less in the frame's vertices and triangles.
  Status track_until(const CancelToken& token, const float* positions, uint32_t n,
                     std::vector<uint32_t>& labels, uint32_t num_clusters, const TrackingOptions& options,
                     uint32_t& bound);
  /// Forgets the previous frame (the next one starts afresh) and frees the buffers.
  void reset();
  bool has_previous() const { return prev_.size() > 0; }

 private:
  /// The previous frame: its matcher, and per vertex in the matcher's cell order its id and
  /// the ids it was given before the vote, newest first (prev_window_ each).
  FrameMatcher prev_;
  std::vector<uint32_t> prev_ids_;
  std::vector<uint32_t> prev_history_;
  /// Per id below prev_bound_, whether prev_history_ holds it (a new cluster must not take it).
  std::vector<bool> prev_used_;
  int prev_window_ = 0;
  uint32_t prev_bound_ = 0;
  /// A frame's buffers, kept between frames (a stream's frames are about one size): the next
  /// matcher (swapped with prev_ once the frame is tracked), ids, lookups, votes, history, used ids.
  FrameMatcher next_;
  std::vector<uint32_t> ids_, nearest_, votes_, history_, sorted_ids_;
  std::vector<bool> used_;
};

}  // namespace fq
