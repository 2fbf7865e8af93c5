#include "kernels/temporal_ids.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

#include "core/cancel_token.h"
#include "core/parallel_for.h"
#include "kernels/frame_prep.h"
#include "kernels/rigid_motion.h"
#include "kernels/temporal.h"
#include "kernels/temporal_math.h"
#include "kernels/vertex_faces.h"
#include "kernels/vertex_ring.h"

namespace fq {

namespace {

// Vertices a worker of the step takes at a time: a range costs some 20 µs (a few ns a vertex
// in each loop), more than waking a pool thread, so a small mesh keeps to few threads.
constexpr int kVertexGrain = 2048;

// SplitMix64's finaliser: every input bit reaches every output bit.
uint64_t mix(uint64_t x) {
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ULL;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

// The sum of the squared weights of vertex v's ring mean (kernels/vertex_ring.h: v once, each
// corner slot once, so a neighbour in two of v's triangles weighs two): the share of white
// noise's variance a ring mean keeps.
float ring_white(const RingView& r, uint32_t v) {
  const uint32_t begin = 2 * r.vf_offsets[v], end = 2 * r.vf_offsets[v + 1];
  float count = 1.f, squares = 1.f;  // v itself
  for (uint32_t k = begin; k < end; ++k) {
    const uint32_t c = r.corners[k];
    if (c == RingView::kNoCorner) continue;
    count += 1.f;
    for (uint32_t j = begin; j < end; ++j) squares += r.corners[j] == c ? 1.f : 0.f;  // Σ multiplicity²
  }
  return squares / (count * count);
}

void restart(const MeshView& mesh, uint64_t fingerprint, IdTrack& track) {
  track.averaged.assign(mesh.positions, mesh.positions + 3 * size_t(mesh.num_vertices));
  track.connectivity = fingerprint;
  track.vertices = mesh.num_vertices;
  track.frames = 1;
  track.stamp = next_history_stamp();
}

// XXH64's round (Collet, xxHash): the lanes of a chunk carry no dependency on each other, so
// a chunk hashes at about an index a cycle where one SplitMix chain through every index waited
// on its two multiplications each time. The ends of the lanes go through mix() in order.
constexpr uint64_t kPrime1 = 0x9e3779b185ebca87ULL, kPrime2 = 0xc2b2ae3d27d4eb4fULL;
uint64_t lane_round(uint64_t acc, uint64_t word) {
  acc += word * kPrime2;
  acc = (acc << 31) | (acc >> 33);
  return acc * kPrime1;
}

uint64_t hash_indices(const uint32_t* t, size_t count, uint32_t chunk) {
  uint64_t lane[4] = {mix(chunk + 1), mix(chunk + 2), mix(chunk + 3), mix(chunk + 4)};
  size_t i = 0;
  for (; i + 8 <= count; i += 8) {
    const uint32_t* w = t + i;
    lane[0] = lane_round(lane[0], uint64_t(w[0]) << 32 | w[1]);
    lane[1] = lane_round(lane[1], uint64_t(w[2]) << 32 | w[3]);
    lane[2] = lane_round(lane[2], uint64_t(w[4]) << 32 | w[5]);
    lane[3] = lane_round(lane[3], uint64_t(w[6]) << 32 | w[7]);
  }
  uint64_t h = mix(count);
  for (; i < count; ++i) h = mix(h ^ t[i]);
  for (uint64_t l : lane) h = mix(h ^ l);
  return h;
}

// The median of the n levels: the element n / 2 of their order, as std::nth_element places it.
// Levels are sums of squares, never negative, so their bit patterns sort as their values do: a
// radix select on the bits (11, 11 and 10 of them) finds that element in three counting passes
// whatever the order of the values (about 0.03 ms less than nth_element on crane's 10K
// vertices). A negative level, an infinity or a NaN (from a broken input)
// goes to nth_element, as before.
float median_level(const std::vector<float>& level, uint32_t n, std::vector<float>& copy) {
  const auto bits = [](float f) { return std::bit_cast<uint32_t>(f); };
  constexpr uint32_t kNotFinite = 0x7f800000u >> 21;  // the first bin of infinities and NaNs
  uint32_t rank = n / 2;
  uint32_t count[1u << 11] = {};
  for (uint32_t v = 0; v < n; ++v) ++count[bits(level[v]) >> 21];
  bool ordinary = true;
  for (uint32_t b = kNotFinite; b < (1u << 11); ++b) ordinary = ordinary && count[b] == 0;
  if (!ordinary) {
    copy.assign(level.begin(), level.begin() + n);
    const auto mid = copy.begin() + rank;
    std::nth_element(copy.begin(), mid, copy.end());
    return *mid;
  }
  // The bin that holds the element `rank` of `count`'s values; `rank` becomes its rank there.
  const auto bin_of = [&](uint32_t bins) {
    uint32_t b = 0;
    for (; rank >= count[b] && b + 1 < bins; ++b) rank -= count[b];
    return b;
  };
  const uint32_t high = bin_of(1u << 11);
  copy.clear();
  for (uint32_t v = 0; v < n; ++v)
    if (bits(level[v]) >> 21 == high) copy.push_back(level[v]);
  std::fill(count, count + (1u << 11), 0u);
  for (float f : copy) ++count[(bits(f) >> 10) & 0x7ffu];
  const uint32_t middle = bin_of(1u << 11);
  std::fill(count, count + (1u << 10), 0u);
  for (float f : copy)
    if (((bits(f) >> 10) & 0x7ffu) == middle) ++count[bits(f) & 0x3ffu];
  const uint32_t low = bin_of(1u << 10);
  return std::bit_cast<float>(high << 21 | middle << 10 | low);
}
// kIdMotionPasses (then kIdWidePasses) more ring means of the rigid fit's inputs, in s.rigid[0..2]
// (through s.rigid[3..5]): the three lanes of one vertex summed side by side.
void rigid_passes(const BlockRing& ring, uint32_t n, TemporalScratch& s, int count, int threads) {
  for (int p = 0; p < count; ++p) {
    for_ring_blocks(
        n, threads,
        [&](uint32_t b, uint32_t v0, uint32_t k) {
          for (int lane = 0; lane < 3; ++lane) {
            Point4 m[kRingBlock];
            block_ring_means(ring, s.rigid[lane].data(), b, m);
            std::copy(m, m + k, s.rigid[3 + lane].data() + v0);
          }
        },
        kVertexGrain);
    for (int lane = 0; lane < 3; ++lane) std::swap(s.rigid[lane], s.rigid[3 + lane]);
  }
}

// The rigid correction at vertex v from the rigid lanes' ring means and the motion's.
Vec3 rigid_at(const TemporalScratch& s, uint32_t v, Vec3 motion) {
  return rigid_correction(RigidInputs{s.rigid[0][v], s.rigid[1][v], s.rigid[2][v]}, motion, s.position[v]);
}

// The id displacement's smooth parts, from s.offset (the displacement d, mean edges): the narrow
// motion m (kIdMotionPasses ring means) and the wide one m' (kIdWidePasses more), each with its
// rigid correction where `rigid` (kernels/rigid_motion.h; s.rigid holds RigidInputs, s.position
// the last averaged positions). Leaves the narrow rest d - m in s.offset, the pair (d - m,
// |d - m|²) in s.packed for the agreement's ring means, and m' - m in s.wide. Each last pass is
// fused with what it leaves; every array it reads has its ring pad set.
void smooth_parts(const BlockRing& ring, uint32_t n, TemporalScratch& s, bool rigid, int threads) {
  static_assert(kIdMotionPasses >= 2 && kIdWidePasses >= 2,
                "the last passes are fused, reading another array");
  const auto each_block = [&](auto&& body) { for_ring_blocks(n, threads, body, kVertexGrain); };
  const auto passes = [&](const Vec3* from, int count) {  // ping-pong through s.motion and s.spare
    std::vector<Vec3>* to = &s.motion;
    std::vector<Vec3>* other = &s.spare;
    for (int p = 0; p < count; ++p) {
      each_block([&](uint32_t b, uint32_t v0, uint32_t k) {
        Vec3 m[kRingBlock];
        block_ring_means(ring, from, b, m);
        std::copy(m, m + k, to->data() + v0);
      });
      from = to->data();
      std::swap(to, other);
    }
    return from;
  };
  const Vec3* from = passes(s.offset.data(), kIdMotionPasses - 1);
  if (rigid) rigid_passes(ring, n, s, kIdMotionPasses, threads);
  each_block([&](uint32_t b, uint32_t v0, uint32_t k) {
    Vec3 m[kRingBlock];
    block_ring_means(ring, from, b, m);
    for (uint32_t j = 0; j < k; ++j) {
      const uint32_t v = v0 + j;
      const Vec3 c = rigid ? rigid_at(s, v, m[j]) : Vec3{0.f, 0.f, 0.f};
      const Vec3 r = s.offset[v] - (m[j] + c);
      s.offset[v] = r;
      s.wide[v] = m[j];
      s.correction[v] = c;
      s.packed[v] = rest_packed(r);
    }
  });
  from = passes(s.wide.data(), kIdWidePasses - 1);
  if (rigid) rigid_passes(ring, n, s, kIdWidePasses, threads);
  each_block([&](uint32_t b, uint32_t v0, uint32_t k) {
    Vec3 m[kRingBlock];
    block_ring_means(ring, from, b, m);
    for (uint32_t j = 0; j < k; ++j) {
      const uint32_t v = v0 + j;
      const Vec3 c = rigid ? rigid_at(s, v, m[j]) : Vec3{0.f, 0.f, 0.f};
      s.wide[v] = (m[j] + c) - (s.wide[v] + s.correction[v]);
    }
  });
}

// Sizes the step's arrays for n vertices, each with the pad its ring means read.
void size_arrays(uint32_t n, TemporalScratch& s) {
  set_ring_pad(s.level, n);
  for (std::vector<Vec3>* f : {&s.offset, &s.motion, &s.spare, &s.wide}) set_ring_pad(*f, n);
  for (std::vector<Point4>* f : {&s.packed, &s.spare_packed}) set_ring_pad(*f, n);
  for (std::vector<Point4>& f : s.rigid) set_ring_pad(f, n);
  s.position.resize(n);
  s.correction.resize(n);
}

// IdTopology::wide_white: white_probe through smooth_parts, and the medians of the local levels
// of the narrow rest and of the wide difference.
float measure_wide_white(const BlockRing& ring, uint32_t n, TemporalScratch& s, int threads) {
  size_arrays(n, s);
  parallel_for(
      n, threads, [&](uint32_t v) { s.offset[v] = white_probe(v); }, kVertexGrain);
  smooth_parts(ring, n, s, false, threads);  // white noise has no rotation to fit
  parallel_for(
      n, threads,
      [&](uint32_t v) {
        s.spare_packed[v] = Point4{s.packed[v].w, dot(s.wide[v], s.wide[v]), 0.f, 0.f};
      },
      kVertexGrain);
  const auto each_block = [&](auto&& body) { for_ring_blocks(n, threads, body, kVertexGrain); };
  static_assert(kIdAgreementPasses == 2, "two passes, as the step's levels");
  each_block([&](uint32_t b, uint32_t v0, uint32_t k) {
    Point4 m[kRingBlock];
    block_ring_means(ring, s.spare_packed.data(), b, m);
    std::copy(m, m + k, s.packed.data() + v0);
  });
  s.spare_level.resize(n);
  each_block([&](uint32_t b, uint32_t v0, uint32_t k) {
    Point4 m[kRingBlock];
    block_ring_means(ring, s.packed.data(), b, m);
    for (uint32_t j = 0; j < k; ++j) {
      s.level[v0 + j] = m[j].x;
      s.spare_level[v0 + j] = m[j].y;
    }
  });
  const float rest = median_level(s.level, n, s.detail);
  const float wide = median_level(s.spare_level, n, s.detail);
  return rest > 0.f ? wide / rest : 0.f;
}

// The connectivity's tables in `topo`, built when it holds another one (`s` lends buffers).
BlockRing keep_topology(const MeshView& mesh, uint64_t fingerprint, IdTopology& topo, TemporalScratch& s,
                        int threads) {
  const uint32_t n = mesh.num_vertices;
  if (!topo.holds(fingerprint, n, mesh.num_triangles)) {
    build_vertex_faces(mesh.triangles, mesh.num_triangles, n, topo.vf_offsets, topo.vf_faces);
    topo.triangles_kept.assign(mesh.triangles, mesh.triangles + 3 * size_t(mesh.num_triangles));
    const FanView fan{mesh.triangles, topo.vf_offsets.data(), topo.vf_faces.data()};
    const RingView ring = build_vertex_ring(fan, n, s.ring_corners, threads);
    build_block_ring(ring, n, topo.ring_rows, topo.ring_slots, topo.ring_inv_count, threads);
    topo.white.resize(n);
    parallel_for(n, threads, [&](uint32_t v) { topo.white[v] = ring_white(ring, v); });
    ring_means(ring, topo.white, s.spare_level, kIdAgreementPasses, threads);
    const BlockRing blocks{topo.ring_rows.data(), topo.ring_slots.data(), topo.ring_inv_count.data(), n, n};
    topo.wide_white = measure_wide_white(blocks, n, s, threads);
    topo.fingerprint = fingerprint;
    topo.vertices = n;
    topo.triangles = mesh.num_triangles;
  }
  return BlockRing{topo.ring_rows.data(), topo.ring_slots.data(), topo.ring_inv_count.data(), n, n};
}

}  // namespace

Vec3 white_probe(uint32_t v) {
  const uint64_t x = mix(uint64_t(v) * 0x9e3779b97f4a7c15ULL + 0x632be59bd9b4e019ULL);  // SplitMix64
  const auto sign = [x](int bit) { return (x >> bit) & 1u ? 1.f : -1.f; };
  return Vec3{sign(0), sign(1), sign(2)};
}

Vec3 id_origin(const MeshView& mesh, int threads) {
  if (mesh.num_vertices == 0) return Vec3{0.f, 0.f, 0.f};
  double lo[3], hi[3];
  mesh_bounds(mesh, lo, hi, threads);  // the bounds are the coordinates' own floats
  const auto mid = [&](int k) { return 0.5f * float(lo[k]) + 0.5f * float(hi[k]); };
  return Vec3{mid(0), mid(1), mid(2)};
}

uint64_t connectivity_fingerprint(const MeshView& mesh, int threads) {
  // Chunks hashed in parallel, then combined in order: the same value for any thread count.
  constexpr uint32_t kChunk = 1u << 14;
  const uint32_t m = mesh.num_triangles;
  const uint32_t chunks = (m + kChunk - 1) / kChunk;
  std::vector<uint64_t> part(chunks);
  parallel_for(
      chunks, threads,
      [&](uint32_t c) {
        const uint32_t* t = mesh.triangles + 3 * size_t(c) * kChunk;
        const size_t count = 3 * size_t(std::min(m, (c + 1) * kChunk) - c * kChunk);  // indices
        part[c] = hash_indices(t, count, c);
      },
      kOneChunkAtATime);
  uint64_t h = mix(uint64_t(mesh.num_vertices) << 32 | 0x9e3779b9u) ^ mix(m);
  for (uint64_t p : part) h = mix(h ^ p);
  return h;
}

uint64_t frame_connectivity(const MeshView& mesh, const IdTrack& track, int threads) {
  const IdTopology& t = track.topology;
  const size_t indices = 3 * size_t(mesh.num_triangles);
  if (t.holds(t.fingerprint, mesh.num_vertices, mesh.num_triangles) && t.triangles_kept.size() == indices &&
      (indices == 0 || std::memcmp(t.triangles_kept.data(), mesh.triangles, indices * sizeof(uint32_t)) == 0))
    return t.fingerprint;
  return connectivity_fingerprint(mesh, threads);
}

size_t IdTrack::bytes() const {
  const IdTopology& t = topology;
  return sizeof(float) * (averaged.capacity() + t.white.capacity() + t.ring_inv_count.capacity()) +
         sizeof(uint32_t) * (t.vf_offsets.capacity() + t.vf_faces.capacity() + t.ring_rows.capacity() +
                             t.ring_slots.capacity() + t.triangles_kept.capacity());
}

bool begin_id_step(const MeshView& mesh, uint64_t fingerprint, double mean_edge, IdTrack& track,
                   TemporalScratch& s, int threads) {
  const uint32_t n = mesh.num_vertices;
  if (track.empty() || track.connectivity != fingerprint || track.vertices != n || n == 0 ||
      !(mean_edge > 0.0)) {
    restart(mesh, fingerprint, track);
    return false;
  }
  keep_topology(mesh, fingerprint, track.topology, s, threads);
  return true;
}

IdStep finish_id_step(const MeshView& mesh, uint64_t fingerprint, const IdMath& math, IdTrack& track) {
  IdStep step;
  step.residual = std::sqrt(math.typical);
  if (!ids_follow(math.typical)) {
    step.refused = true;
    restart(mesh, fingerprint, track);
    return step;
  }
  track.frames = track.frames < kIdFramesCounted ? track.frames + 1 : kIdFramesCounted;
  track.stamp = next_history_stamp();
  const uint32_t n = mesh.num_vertices;
  step.share = float(math.share_sum / n);
  step.wide = float(math.wide_sum / n);
  step.ran = true;
  return step;
}

IdStep average_with_ids(const MeshView& mesh, uint64_t fingerprint, double mean_edge, float strength,
                        IdTrack& track, std::vector<float>& averaged, TemporalScratch& s, int threads) {
  // Each loop's result is read by the next; the step is short: it runs whole.
  const CancelScope whole(nullptr);
  if (!begin_id_step(mesh, fingerprint, mean_edge, track, s, threads)) return IdStep{};
  const uint32_t n = mesh.num_vertices;
  const IdTopology& topo = track.topology;
  const BlockRing ring{topo.ring_rows.data(), topo.ring_slots.data(), topo.ring_inv_count.data(), n, n};
  const float* white = topo.white.data();
  // The displacement from the last averaged input, in mean edges (a difference of nearby
  // points: floats keep their precision without an origin). Each loop below also does what
  // the ring means before it allow for its vertices: the sums are those of a loop per quantity.
  // Every array a ring mean reads has the pad element past its n values.
  const float unit = float(1.0 / mean_edge);
  const float* x = mesh.positions;
  float* a = track.averaged.data();
  size_arrays(n, s);
  s.share.resize(n);
  s.spare_level.resize(n);
  averaged.resize(3 * size_t(n));
  const auto each_block = [&](auto&& body) { for_ring_blocks(n, threads, body, kVertexGrain); };
  // The last averaged positions in mean edges from the frame's origin, for the rigid fit.
  const Vec3 origin = id_origin(mesh, threads);
  parallel_for(
      n, threads,
      [&](uint32_t v) {
        const IdPoint at = id_point(x, a, v, unit, origin);
        s.offset[v] = at.d;
        s.position[v] = at.p;
        const RigidInputs in = rigid_inputs(at.p, at.d);
        s.rigid[0][v] = in.p;
        s.rigid[1][v] = in.q0;
        s.rigid[2][v] = in.q1;
      },
      kVertexGrain);
  // The motion's two estimates: the narrow rest in s.offset (and packed with its square), the
  // wide estimate's difference from the narrow one in s.wide.
  smooth_parts(ring, n, s, true, threads);
  // The local level (kIdAgreementPasses ring means of the square) beside the coherence test:
  // the square of the rest's ring mean, then its ring means, one pass behind, and the wide
  // difference's local level as well. Each pass's ring means run together, one quantity to a
  // lane: the rest and its square; then the level, the coherence test's square and the wide
  // difference's square; then the last two.
  static_assert(kIdAgreementPasses == 2, "the level's and the coherence test's passes are fused in pairs");
  each_block([&](uint32_t b, uint32_t v0, uint32_t k) {
    Point4 m[kRingBlock];
    block_ring_means(ring, s.packed.data(), b, m);
    for (uint32_t j = 0; j < k; ++j) s.spare_packed[v0 + j] = level_inputs(m[j], s.wide[v0 + j]);
  });
  each_block([&](uint32_t b, uint32_t v0, uint32_t k) {
    Point4 m[kRingBlock];
    block_ring_means(ring, s.spare_packed.data(), b, m);
    for (uint32_t j = 0; j < k; ++j) {
      s.level[v0 + j] = m[j].x;
      s.packed[v0 + j] = Point4{m[j].y, m[j].z, 0.f, 0.f};
    }
  });
  IdMath math;
  math.typical = median_level(s.level, n, s.detail);
  if (!ids_follow(math.typical)) return finish_id_step(mesh, fingerprint, math, track);
  // The averaged input, which the track keeps for the next frame (it read its offsets above).
  // Each vertex's motion is the narrow estimate plus the share of the wide one's difference
  // that its noise allows (wide_share); what is left of the displacement is averaged out.
  const IdBlend blend{id_history_weight(track, strength), math.typical, topo.wide_white, float(mean_edge)};
  each_block([&](uint32_t b, uint32_t v0, uint32_t k) {
    Point4 m[kRingBlock];
    block_ring_means(ring, s.packed.data(), b, m);  // the coherence test's level, the wide one's
    for (uint32_t j = 0; j < k; ++j) {
      const uint32_t v = v0 + j;
      const IdWeights w = blend.weights(m[j], s.level[v], white[v]);
      s.spare_level[v] = w.wide;
      s.share[v] = w.share;
      const Vec3 back = blend.back(w, s.offset[v], s.wide[v]);  // input units
      const size_t i = 3 * size_t(v);
      averaged[i] = a[i] = x[i] - back.x;
      averaged[i + 1] = a[i + 1] = x[i + 1] - back.y;
      averaged[i + 2] = a[i + 2] = x[i + 2] - back.z;
    }
  });
  for (uint32_t v = 0; v < n; ++v) {  // in order: the report is reproducible
    math.share_sum += s.share[v];
    math.wide_sum += s.spare_level[v];
  }
  return finish_id_step(mesh, fingerprint, math, track);
}

float id_history_weight(const IdTrack& track, float strength) {
  return history_weight(strength, track.frames);
}

void keep_averaged_result(const MeshView& mesh, const std::vector<float>& positions, double mean_edge,
                          TemporalHistory& history) {
  history.positions.assign(positions.begin(), positions.begin() + 3 * size_t(mesh.num_vertices));
  history.normals.clear();
  history.motion.clear();
  history.normals_pending = history.ids.topology.fingerprint;
  history.mean_edge = mean_edge;
  history.stamp = next_history_stamp();  // the index is built when the next frame needs it
  ++history.frames;
}

}  // namespace fq
