#include "kernels/vertex_ring.h"

#include "core/parallel_for.h"

namespace fq {

RingView build_vertex_ring(const FanView& fan, uint32_t n, std::vector<uint32_t>& corners, int threads) {
  corners.resize(2 * size_t(fan.vf_offsets[n]));
  parallel_for(n, threads, [&](uint32_t v) {
    for (uint32_t k = fan.vf_offsets[v]; k < fan.vf_offsets[v + 1]; ++k) {
      const uint32_t* tri = fan.tris + 3 * size_t(fan.vf_faces[k]);
      uint32_t* slot = corners.data() + 2 * size_t(k);
      slot[0] = slot[1] = RingView::kNoCorner;
      for (int c = 0; c < 3; ++c)
        if (tri[c] != v) *slot++ = tri[c];
    }
  });
  return RingView{fan.vf_offsets, corners.data()};
}

}  // namespace fq
