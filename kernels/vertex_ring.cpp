#include "kernels/vertex_ring.h"

#include "core/parallel_for.h"

namespace fq {

RingView build_vertex_ring(const FanView& fan, uint32_t n, std::vector<uint32_t>& corners, int threads) {
  corners.resize(2 * size_t(fan.vf_offsets[n]));
  parallel_for(n, threads, [&](uint32_t v) { ring_slots(fan, v, corners.data()); });
  return RingView{fan.vf_offsets, corners.data()};
}

BlockRing build_block_ring(const RingView& ring, uint32_t n, std::vector<uint32_t>& rows,
                           std::vector<uint32_t>& slots, std::vector<float>& inv_count, int threads) {
  const auto size = [&](uint32_t v) {
    uint32_t k = 0;
    for (uint32_t s = 2 * ring.vf_offsets[v]; s < 2 * ring.vf_offsets[v + 1]; ++s)
      k += ring.corners[s] != RingView::kNoCorner;
    return k;
  };
  const uint32_t blocks = (n + kRingBlock - 1) / kRingBlock;
  rows.resize(size_t(blocks) + 1);
  rows[0] = 0;
  inv_count.resize(size_t(n) + 1);
  inv_count[n] = 1.f;
  parallel_for(blocks, threads, [&](uint32_t b) {
    uint32_t widest = 0;
    for (uint32_t v = b * kRingBlock; v < n && v < (b + 1) * kRingBlock; ++v) {
      const uint32_t k = size(v);
      widest = k > widest ? k : widest;
      inv_count[v] = 1.f / float(1 + k);  // ring_mean's count: 1 + k ones added, exact
    }
    rows[b + 1] = widest;
  });
  for (uint32_t b = 0; b < blocks; ++b) rows[b + 1] += rows[b];
  slots.resize(size_t(kRingBlock) * rows[blocks]);
  parallel_for(blocks, threads, [&](uint32_t b) {
    uint32_t* row0 = slots.data() + size_t(kRingBlock) * rows[b];
    const uint32_t width = rows[b + 1] - rows[b];
    for (uint32_t j = 0; j < kRingBlock; ++j) {
      const uint32_t v = b * kRingBlock + j;
      uint32_t r = 0;
      if (v < n)
        for (uint32_t s = 2 * ring.vf_offsets[v]; s < 2 * ring.vf_offsets[v + 1]; ++s)
          if (ring.corners[s] != RingView::kNoCorner) row0[kRingBlock * r++ + j] = ring.corners[s];
      for (; r < width; ++r) row0[kRingBlock * r + j] = n;  // the pad
    }
  });
  return BlockRing{rows.data(), slots.data(), inv_count.data(), n, n};
}

}  // namespace fq
