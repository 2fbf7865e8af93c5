// Quick shift's link forest before the theta cut, and the labels it gives at any cut.
// Alg. 1 links every vertex to its best higher-ranked neighbour and cuts the links whose
// proximity p is below 1 - theta; the links themselves do not depend on theta. So one link
// pass gives the labels at every theta, and the theta that gives K clusters follows from
// one sort of the link proximities: clusters(cut) = permanent roots + #{links with p < cut}.
#pragma once

#include <cstdint>
#include <vector>

namespace fq {

/// Per vertex: the vertex it links to (itself for a root at every theta) and the link's p.
struct LinkForest {
  const uint32_t* parent = nullptr;
  const float* p = nullptr;
  uint32_t n = 0;
};

/// Labels when links with p < cut are cut, numbered 0..K-1 in the input order of the
/// root vertices (as the engines number them); returns K.
uint32_t labels_at_cut(const LinkForest& forest, float cut, std::vector<uint32_t>& labels);

/// The cuts that matter, in increasing order: candidate t (0 <= t <= links()) cuts
/// exactly the t weakest links (ties aside) and gives roots() + t clusters.
class CutLadder {
 public:
  explicit CutLadder(const LinkForest& forest);
  uint32_t roots() const { return roots_; }
  uint32_t links() const { return static_cast<uint32_t>(sorted_.size()); }
  /// Cut value for `t` cut links: 0 for none, above every p for t = links(), else halfway
  /// between the t-th and (t+1)-th weakest p.
  float cut(uint32_t t) const;
  /// The t that gives `target` clusters without ties (clamped to [0, links()]).
  uint32_t t_for(uint32_t target) const;

 private:
  std::vector<float> sorted_;  ///< p of every non-root link, ascending
  uint32_t roots_ = 0;
};

/// theta whose cut (1 - theta) is `cut`, clamped into (0, 1].
float theta_for_cut(float cut);

}  // namespace fq
