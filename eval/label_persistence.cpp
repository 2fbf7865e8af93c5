#include "eval/label_persistence.h"

#include <limits>
#include <vector>

#include "kernels/nearest_vertex.h"

namespace fq {

double label_persistence(const float* prev_xyz, const uint32_t* prev_labels, uint32_t prev_n,
                         const float* cur_xyz, const uint32_t* cur_labels, uint32_t cur_n, float cell,
                         int threads) {
  if (cur_n == 0) return std::numeric_limits<double>::quiet_NaN();
  NearestVertexIndex prev;
  prev.build(prev_xyz, prev_n, cell);
  std::vector<uint32_t> nearest;
  prev.nearest_all(cur_xyz, cur_n, std::numeric_limits<float>::infinity(), nearest, threads);
  uint64_t same = 0;
  for (uint32_t v = 0; v < cur_n; ++v)
    same += nearest[v] != NearestVertexIndex::kNone && prev_labels[nearest[v]] == cur_labels[v];
  return double(same) / double(cur_n);
}

}  // namespace fq
