#include "kernels/cluster_forest.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fq {

namespace {
constexpr uint32_t kUnset = std::numeric_limits<uint32_t>::max();
}

uint32_t labels_at_cut(const LinkForest& f, float cut, std::vector<uint32_t>& labels) {
  auto is_root = [&](uint32_t i) { return f.parent[i] == i || f.p[i] < cut; };
  // Roots get labels in increasing vertex index, then every vertex climbs to its root;
  // `labels` doubles as the memo, so each chain is walked once.
  labels.assign(f.n, kUnset);
  uint32_t k = 0;
  for (uint32_t i = 0; i < f.n; ++i) {
    if (is_root(i)) labels[i] = k++;
  }
  std::vector<uint32_t> path;
  for (uint32_t i = 0; i < f.n; ++i) {
    uint32_t cur = i;
    while (labels[cur] == kUnset) {
      path.push_back(cur);
      cur = f.parent[cur];
    }
    for (uint32_t v : path) labels[v] = labels[cur];
    path.clear();
  }
  return k;
}

CutLadder::CutLadder(const LinkForest& f) {
  for (uint32_t i = 0; i < f.n; ++i) {
    if (f.parent[i] == i)
      ++roots_;
    else
      sorted_.push_back(f.p[i]);
  }
  std::sort(sorted_.begin(), sorted_.end());
}

float CutLadder::cut(uint32_t t) const {
  // Halfway between the last link cut and the first kept, so that theta = 1 - cut survives
  // float rounding when given back; no cut at all is theta = 1.
  if (t == 0) return 0.f;
  if (t < sorted_.size()) return 0.5f * (sorted_[t - 1] + sorted_[t]);
  const float top = sorted_.empty() ? 0.f : sorted_.back();
  return std::nextafter(std::max(top, 0.f), std::numeric_limits<float>::infinity());
}

uint32_t CutLadder::t_for(uint32_t target) const {
  if (target <= roots_) return 0;
  return std::min<uint32_t>(target - roots_, links());
}

float theta_for_cut(float cut) {
  const float theta = 1.0f - cut;
  return std::clamp(theta, std::numeric_limits<float>::min(), 1.0f);
}

}  // namespace fq
