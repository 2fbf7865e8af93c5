#include "kernels/temporal_ids.h"

#include <algorithm>
#include <cmath>

#include "core/cancel_token.h"
#include "core/parallel_for.h"
#include "kernels/temporal.h"
#include "kernels/temporal_math.h"
#include "kernels/vertex_faces.h"
#include "kernels/vertex_ring.h"

namespace fq {

namespace {

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
}

}  // namespace

uint64_t connectivity_fingerprint(const MeshView& mesh, int threads) {
  // Chunks hashed in parallel, then combined in order: the same value for any thread count.
  constexpr uint32_t kChunk = 1u << 14;
  const uint32_t m = mesh.num_triangles;
  const uint32_t chunks = (m + kChunk - 1) / kChunk;
  std::vector<uint64_t> part(chunks);
  parallel_for(
      chunks, threads,
      [&](uint32_t c) {
        uint64_t h = mix(c + 1);
        const uint32_t end = std::min(m, (c + 1) * kChunk);
        for (size_t i = 3 * size_t(c) * kChunk; i < 3 * size_t(end); ++i) h = mix(h ^ mesh.triangles[i]);
        part[c] = h;
      },
      kOneChunkAtATime);
  uint64_t h = mix(uint64_t(mesh.num_vertices) << 32 | 0x9e3779b9u) ^ mix(m);
  for (uint64_t p : part) h = mix(h ^ p);
  return h;
}

IdStep average_with_ids(const MeshView& mesh, uint64_t fingerprint, double mean_edge, float strength,
                        IdTrack& track, std::vector<float>& averaged, TemporalScratch& s, int threads) {
  // Each loop's result is read by the next; the step is short: it runs whole.
  const CancelScope whole(nullptr);
  const uint32_t n = mesh.num_vertices;
  IdStep step;
  if (track.empty() || track.connectivity != fingerprint || track.vertices != n || n == 0 ||
      !(mean_edge > 0.0)) {
    restart(mesh, fingerprint, track);
    return step;
  }
  build_vertex_faces(mesh.triangles, mesh.num_triangles, n, s.vf_offsets, s.vf_faces);
  const FanView fan{mesh.triangles, s.vf_offsets.data(), s.vf_faces.data()};
  const RingView ring = build_vertex_ring(fan, n, s.ring_corners, threads);
  // The displacement from the last averaged input, in mean edges (a difference of nearby
  // points: floats keep their precision without an origin).
  const float unit = float(1.0 / mean_edge);
  const float* x = mesh.positions;
  const float* a = track.averaged.data();
  s.offset.resize(n);
  parallel_for(n, threads, [&](uint32_t v) {
    const size_t i = 3 * size_t(v);
    s.offset[v] = unit * Vec3{x[i] - a[i], x[i + 1] - a[i + 1], x[i + 2] - a[i + 2]};
  });
  s.motion = s.offset;
  ring_means(ring, s.motion, s.spare, kIdMotionPasses, threads);
  // What the motion leaves: the non-smooth displacement, and its local level.
  s.level.resize(n);
  parallel_for(n, threads, [&](uint32_t v) {
    s.offset[v] = s.offset[v] - s.motion[v];
    s.level[v] = dot(s.offset[v], s.offset[v]);
  });
  ring_means(ring, s.level, s.spare_level, kIdAgreementPasses, threads);
  // The coherence test: how much of the rest survives a ring mean, against white noise's share.
  s.coherent.resize(n);
  s.white.resize(n);
  parallel_for(n, threads, [&](uint32_t v) {
    const Vec3 c = ring_mean(ring, s.offset.data(), v);
    s.coherent[v] = dot(c, c);
    s.white[v] = ring_white(ring, v);
  });
  ring_means(ring, s.coherent, s.spare_level, kIdAgreementPasses, threads);
  ring_means(ring, s.white, s.spare_level, kIdAgreementPasses, threads);
  s.detail.assign(s.level.begin(), s.level.end());  // the median's copy
  const auto mid = s.detail.begin() + n / 2;
  std::nth_element(s.detail.begin(), mid, s.detail.end());
  const float typical = *mid;
  step.residual = std::sqrt(typical);
  if (!ids_follow(typical)) {
    step.refused = true;
    restart(mesh, fingerprint, track);
    return step;
  }
  averaged.resize(3 * size_t(n));
  s.share.resize(n);
  const float edge = float(mean_edge);
  parallel_for(n, threads, [&](uint32_t v) {
    s.share[v] = id_share(s.level[v], typical, strength) * noise_part(s.coherent[v], s.level[v], s.white[v]);
    const Vec3 back = (s.share[v] * edge) * s.offset[v];  // x - share * (non-smooth part), input units
    const size_t i = 3 * size_t(v);
    averaged[i] = x[i] - back.x;
    averaged[i + 1] = x[i + 1] - back.y;
    averaged[i + 2] = x[i + 2] - back.z;
  });
  double total = 0.0;
  for (uint32_t v = 0; v < n; ++v) total += s.share[v];  // in order: the report is reproducible
  step.share = float(total / n);
  step.ran = true;
  track.averaged.assign(averaged.begin(), averaged.end());
  return step;
}

void keep_averaged_result(const MeshView& mesh, const std::vector<float>& positions, double mean_edge,
                          TemporalHistory& history, TemporalScratch& s, int threads) {
  // average_with_ids built the frame's vertex -> triangles table into the scratch when it ran,
  // and the run between does not touch the temporal scratch: no second build.
  const FanView fan{mesh.triangles, s.vf_offsets.data(), s.vf_faces.data()};
  keep_as_history(fan, mesh.num_vertices, positions, mean_edge, history, s, threads);
}

}  // namespace fq
