// Vertex -> the other corners of its triangles, in the order ring_mean (kernels/refine_math.h)
// visits them over the vertex's fan: a table built once per frame, so a run of ring means reads
// each neighbour index directly instead of going through the triangles each pass. The sums, and
// so the results, are the same bit for bit as ring_mean over the fan.
#pragma once

#include <cstdint>
#include <cstring>
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

/// Vertex v's slots of the table (`corners`: the whole table): what build_vertex_ring writes
/// for it, and the CUDA engine's table kernel.
FQ_HD void ring_slots(const FanView& fan, uint32_t v, uint32_t* corners) {
  for (uint32_t k = fan.vf_offsets[v]; k < fan.vf_offsets[v + 1]; ++k) {
    const uint32_t* tri = fan.tris + 3 * size_t(fan.vf_faces[k]);
    uint32_t* slot = corners + 2 * size_t(k);
    slot[0] = slot[1] = RingView::kNoCorner;
    for (int c = 0; c < 3; ++c)
      if (tri[c] != v) *slot++ = tri[c];
  }
}

/// ring_mean(fan, e, v) through the table: the same additions in the same order. `e` is
/// anything indexed by vertex: an array of T, or a Lane of an array of structs.
template <class T, class Elements>
FQ_HD T ring_mean_of(const RingView& r, const Elements& e, uint32_t v) {
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

template <class T>
FQ_HD T ring_mean(const RingView& r, const T* e, uint32_t v) {
  return ring_mean_of<T>(r, e, v);
}

/// Vertex u's T in an array of structs of kLanes T each, starting at `first` (one lane of them):
/// the CUDA engine's ring means of a 64-byte struct run a thread a lane.
template <class T, uint32_t kLanes>
struct Lane {
  const T* first;
  FQ_HD T operator[](uint32_t u) const { return first[size_t(kLanes) * u]; }
};

/// Vertices whose ring sums run side by side (block_ring_means).
inline constexpr uint32_t kRingBlock = 4;

/// The ring table in blocks of kRingBlock vertices, for a stream that keeps its connectivity
/// (kernels/temporal_ids.h) and runs many ring means over one table. Block b's rows are
/// [rows[b], rows[b + 1]); row r holds slot r of each of the block's vertices at
/// slots[kRingBlock r + j], in the table's order without its kNoCorner slots. A vertex with fewer
/// neighbours than its block's widest, and a lane past the last vertex, reads `pad` (the n-th
/// element of the summed array, which the caller sets to -0.0: x + (-0.0) is x, bit for bit,
/// for every float x).
struct BlockRing {
  const uint32_t* rows;     ///< blocks + 1
  const uint32_t* slots;    ///< kRingBlock per row
  const float* inv_count;   ///< per vertex: 1 / (1 + its neighbours), as ring_mean divides
  uint32_t n = 0, pad = 0;  ///< pad == n
};

/// The block table of `ring`'s n vertices into `rows`, `slots` and `inv_count`.
BlockRing build_block_ring(const RingView& ring, uint32_t n, std::vector<uint32_t>& rows,
                           std::vector<uint32_t>& slots, std::vector<float>& inv_count, int threads);

/// Sets the pad element of `e` (then n + 1 elements) that block_ring_means reads for missing slots.
inline void set_ring_pad(std::vector<float>& e, uint32_t n) {
  e.resize(size_t(n) + 1);
  e[n] = -0.f;
}
inline void set_ring_pad(std::vector<Point4>& e, uint32_t n) {
  e.resize(size_t(n) + 1);
  e[n] = Point4{-0.f, -0.f, -0.f, -0.f};
}
inline void set_ring_pad(std::vector<Vec3>& e, uint32_t n) {  // and one more: see Float4 below
  e.resize(size_t(n) + 2);
  e[n] = e[n + 1] = Vec3{-0.f, -0.f, -0.f};
}

namespace detail {

/// The block's four sums of load(i) over its vertices' rings, times their 1 / count, in m.
/// Four named sums: an array of them stays in memory, one store a row.
template <class S, class Load>
void block_ring_sums(const BlockRing& r, uint32_t b, Load load, S* m) {
  static_assert(kRingBlock == 4, "four named sums");
  const uint32_t v0 = b * kRingBlock;
  const auto lane = [&](uint32_t j) { return v0 + j < r.n ? v0 + j : r.pad; };
  S s0 = load(lane(0)), s1 = load(lane(1)), s2 = load(lane(2)), s3 = load(lane(3));
  const uint32_t* s = r.slots + size_t(kRingBlock) * r.rows[b];
  const uint32_t* end = r.slots + size_t(kRingBlock) * r.rows[b + 1];
  for (; s != end; s += kRingBlock) {
    s0 = s0 + load(s[0]);
    s1 = s1 + load(s[1]);
    s2 = s2 + load(s[2]);
    s3 = s3 + load(s[3]);
  }
  m[0] = r.inv_count[lane(0)] * s0;
  m[1] = r.inv_count[lane(1)] * s1;
  m[2] = r.inv_count[lane(2)] * s2;
  m[3] = r.inv_count[lane(3)] * s3;
}

}  // namespace detail

/// ring_mean(r, e, v) (kernels/vertex_ring.h's table) for the vertices of block b, into
/// out[0 .. kRingBlock) (lanes past the last vertex get the pad's mean). e holds n + 1 elements,
/// e[n] = -0.0. Each vertex's sum is its own chain of additions in ring_mean's order, padded
/// with -0.0 (which changes no bit), so the result is ring_mean's; the block's four chains
/// overlap where one alone would wait on each addition in turn.
inline void block_ring_means(const BlockRing& r, const float* e, uint32_t b, float* out) {
  detail::block_ring_sums(
      r, b, [e](uint32_t i) { return e[i]; }, out);
}

/// Four floats added lane by lane (GCC's and Clang's vector extension, on every target): a Vec3
/// sum in one addition a slot, from a 16-byte load of the element and the next one's x, whose
/// lane is dropped. Each lane's additions are the scalar ones, so x, y and z keep their bits.
using Float4 = float __attribute__((vector_size(16)));

namespace detail {

/// The 16 bytes at p: a Point4, or a Vec3 and the next element's x (set_ring_pad's spare past
/// the last).
template <class T>
Float4 load4(const T* p) {
  Float4 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

}  // namespace detail

/// block_ring_means for Vec3 (e from set_ring_pad: n + 2 elements).
inline void block_ring_means(const BlockRing& r, const Vec3* e, uint32_t b, Vec3* out) {
  Float4 m[kRingBlock];
  detail::block_ring_sums(
      r, b, [e](uint32_t i) { return detail::load4(e + i); }, m);
  for (uint32_t j = 0; j < kRingBlock; ++j) out[j] = Vec3{m[j][0], m[j][1], m[j][2]};
}

/// block_ring_means for Point4: four quantities of a vertex in one addition a slot (e from
/// set_ring_pad: n + 1 elements).
inline void block_ring_means(const BlockRing& r, const Point4* e, uint32_t b, Point4* out) {
  static_assert(sizeof(Point4) == sizeof(Float4));
  Float4 m[kRingBlock];
  detail::block_ring_sums(
      r, b, [e](uint32_t i) { return detail::load4(e + i); }, m);
  for (uint32_t j = 0; j < kRingBlock; ++j) out[j] = Point4{m[j][0], m[j][1], m[j][2], m[j][3]};
}

/// body(b, v0, count) for each block b of the n vertices (vertices v0 .. v0 + count), in
/// parallel on up to `threads` threads, `grain` vertices at a time (a multiple of kRingBlock).
template <class F>
void for_ring_blocks(uint32_t n, int threads, F&& body, int grain) {
  const uint32_t blocks = (n + kRingBlock - 1) / kRingBlock;
  parallel_for(
      blocks, threads,
      [&](uint32_t b) {
        const uint32_t v0 = b * kRingBlock;
        body(b, v0, n - v0 < kRingBlock ? n - v0 : kRingBlock);
      },
      grain / int(kRingBlock));
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
