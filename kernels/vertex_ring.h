// Vertex -> the other corners of its triangles, in the order ring_mean (kernels/refine_math.h)
// visits them over the vertex's fan: a table built once per frame, so a run of ring means reads
// each neighbour index directly instead of going through the triangles each pass. The sums, and
// so the results, are the same bit for bit as ring_mean over the fan.
#pragma once

#include <cstdint>
#include <vector>

#include "core/parallel_for.h"
#include "kernels/refine_math.h"

namespace fq {

/// Two slots per entry of the fan (a vertex is a corner of each of its triangles, so at most two
/// others are): vertex v's ring is corners[2 vf_offsets[v] .. 2 vf_offsets[v + 1]), in fan order,
/// a slot left kNoCorner where a degenerate triangle repeats v. The fixed layout lets every
/// vertex write its slots at once, without a count and a prefix sum first.
struct RingView {
  static constexpr uint32_t kNoCorner = 0xffffffffu;
  const uint32_t* vf_offsets;  ///< the fan's, n + 1
  const uint32_t* corners;
};

/// The ring table of the n vertices of `fan` into `corners`, on up to `threads` threads.
RingView build_vertex_ring(const FanView& fan, uint32_t n, std::vector<uint32_t>& corners, int threads);

/// ring_mean(fan, e, v) through the table: the same additions in the same order.
template <class T>
T ring_mean(const RingView& r, const T* e, uint32_t v) {
  T sum = e[v];
  float count = 1.f;
  for (uint32_t k = 2 * r.vf_offsets[v]; k < 2 * r.vf_offsets[v + 1]; ++k) {
    const uint32_t c = r.corners[k];
    if (c == RingView::kNoCorner) continue;
    sum = sum + e[c];
    count += 1.f;
  }
  return (1.f / count) * sum;
}

/// `passes` ring means of `a` over the table, in parallel on up to `threads` threads; `spare` is
/// the other buffer (its contents are left over).
template <class T>
void ring_means(const RingView& ring, std::vector<T>& a, std::vector<T>& spare, int passes, int threads) {
  spare.resize(a.size());
  for (int p = 0; p < passes; ++p) {
    parallel_for(static_cast<uint32_t>(a.size()), threads,
                 [&](uint32_t v) { spare[v] = ring_mean(ring, a.data(), v); });
    a.swap(spare);
  }
}

}  // namespace fq
