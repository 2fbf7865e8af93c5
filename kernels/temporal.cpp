#include "kernels/temporal.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include "core/cancel_token.h"
#include "core/parallel_for.h"
#include "kernels/refine_math.h"
#include "kernels/temporal_math.h"
#include "kernels/vertex_faces.h"
#include "kernels/vertex_ring.h"

namespace fq {

namespace {

Vec3 at(const float* xyz, uint32_t v) {
  return {xyz[3 * size_t(v)], xyz[3 * size_t(v) + 1], xyz[3 * size_t(v) + 2]};
}

}  // namespace

uint64_t next_history_stamp() {
  static std::atomic<uint64_t> next{1};
  return next.fetch_add(1, std::memory_order_relaxed);
}

void vertex_normals(const FanView& fan, uint32_t n, const float* positions, std::vector<Vec3>& faces,
                    std::vector<float>& out, int threads) {
  // Each triangle's cross product once (vertex_normal computes it once per corner: the same
  // expression, so the same bits), then each vertex's sum over its fan in fan order. A range of
  // kGrain items is a few µs of work, more than waking a pool thread for it.
  constexpr int kGrain = 2048;
  const uint32_t m = fan.vf_offsets[n] / 3;  // every triangle is in the fans of its 3 corners
  faces.resize(m);
  parallel_for(
      m, threads,
      [&](uint32_t f) {
        const uint32_t* tri = fan.tris + 3 * size_t(f);
        const Vec3 a = at(positions, tri[0]);
        faces[f] = cross(at(positions, tri[1]) - a, at(positions, tri[2]) - a);
      },
      kGrain);
  out.resize(3 * size_t(n));
  parallel_for(
      n, threads,
      [&](uint32_t v) {
        Vec3 acc{0.f, 0.f, 0.f};
        for (uint32_t k = fan.vf_offsets[v]; k < fan.vf_offsets[v + 1]; ++k)
          acc = acc + faces[fan.vf_faces[k]];
        const Vec3 u = normalized_or_zero(acc);
        out[3 * size_t(v)] = u.x;
        out[3 * size_t(v) + 1] = u.y;
        out[3 * size_t(v) + 2] = u.z;
      },
      kGrain);
}

void keep_as_history(const FanView& fan, uint32_t n, const std::vector<float>& positions, double mean_edge,
                     TemporalHistory& history, TemporalScratch& s, int threads) {
  const CancelScope whole(nullptr);
  vertex_normals(fan, n, positions.data(), s.spare, s.normals, threads);
  history.positions.assign(positions.begin(), positions.begin() + 3 * size_t(n));
  history.normals.swap(s.normals);
  history.motion.clear();
  history.normals_pending = 0;
  history.mean_edge = mean_edge;
  history.stamp = next_history_stamp();  // the index is built when the next frame needs it
  ++history.frames;
}

void settle_history_normals(TemporalHistory& history, TemporalScratch& s, int threads) {
  if (history.normals_pending == 0) return;
  const IdTopology& t = history.ids.topology;
  const uint32_t n = t.vertices;
  if (t.fingerprint != history.normals_pending || t.triangles_kept.size() != 3 * size_t(t.triangles) ||
      history.positions.size() != 3 * size_t(n)) {
    history.clear();
    return;
  }
  const CancelScope whole(nullptr);
  const FanView fan{t.triangles_kept.data(), t.vf_offsets.data(), t.vf_faces.data()};
  vertex_normals(fan, n, history.positions.data(), s.spare, history.normals, threads);
  history.normals_pending = 0;
}

TemporalStep follow_history(const MeshView& mesh, std::vector<float>& positions, double mean_edge,
                            float noise, float strength, TemporalHistory& history, TemporalScratch& s,
                            int threads) {
  // No loop of the step may be skipped (parallel_for skips chunks under an expired token): the
  // serial code after each loop reads what it wrote, and the step is short. It runs whole.
  const CancelScope whole(nullptr);
  const uint32_t n = mesh.num_vertices;
  TemporalStep step;
  settle_history_normals(history, s, threads);  // where track A left them (Engine::run_own settles first)
  const bool follows = !history.empty() && n > 0 && mean_edge > 0.0;
  // The frame's vertex -> triangles table (for the ring means and the normals) and the index of
  // the last result (when the last frame's engine left none) are two serial builds that do not
  // depend on each other: side by side on two threads.
  const bool index_needed = follows && history.index_stamp != history.stamp;
  parallel_for(
      index_needed ? 2 : 1, threads,
      [&](uint32_t task) {
        if (task == 0)
          build_vertex_faces(mesh.triangles, mesh.num_triangles, n, s.vf_offsets, s.vf_faces);
        else
          history.index.build(history.positions.data(), uint32_t(history.positions.size() / 3),
                              float(history.mean_edge));
      },
      kOneChunkAtATime);
  if (index_needed) history.index_stamp = history.stamp;
  const FanView fan{mesh.triangles, s.vf_offsets.data(), s.vf_faces.data()};
  if (follows) {
    // Six ring means follow: the table saves each of them the walk through the triangles.
    const RingView ring = build_vertex_ring(fan, n, s.ring_corners, threads);
    // The math runs in mean edges about the first vertex (floats keep their precision there).
    const Vec3 origin = at(positions.data(), 0);
    const float unit = float(1.0 / mean_edge);
    const auto normalized = [&](const float* p) { return unit * (Vec3{p[0], p[1], p[2]} - origin); };
    const auto prior_at = [&](uint32_t q) { return normalized(&history.positions[3 * size_t(q)]); };
    const auto normal_at = [&](uint32_t q) { return at(history.normals.data(), q); };
    s.x.resize(n);
    parallel_for(n, threads, [&](uint32_t v) { s.x[v] = normalized(&positions[3 * size_t(v)]); });
    s.motion.assign(n, Vec3{0.f, 0.f, 0.f});
    s.match.resize(n);
    s.lanes.resize(n);
    const float reach = float(kPriorReach * mean_edge);  // input units, as the index
    // Each lookup from the last motion estimate, then record(v) with the match in s.match[v].
    const auto look_up = [&](auto&& record) {
      parallel_for(n, threads, [&](uint32_t v) {
        const Vec3 q = origin + float(mean_edge) * (s.x[v] + s.motion[v]);
        s.match[v] = history.index.nearest(q, reach);
        record(v);
      });
    };
    const auto match_only = [](uint32_t) {};
    // A vertex's offset to its match; one that finds none counts as no motion.
    const auto offset_of = [&](uint32_t v) {
      return s.match[v] == FrameMatcher::kNone ? Vec3{0.f, 0.f, 0.f} : prior_at(s.match[v]) - s.x[v];
    };
    if (history.motion.size() == history.positions.size()) {  // the prediction, from x
      look_up(match_only);
      parallel_for(n, threads, [&](uint32_t v) {
        const uint32_t q = s.match[v];
        const bool found = q != FrameMatcher::kNone;
        s.motion[v] =
            predicted_motion(found, found ? at(history.motion.data(), q) : Vec3{0.f, 0.f, 0.f}, unit);
      });
      ring_means(ring, s.motion, s.spare, kPredictionPasses, threads);
    }
    for (int it = 0; it < kMotionIterations; ++it) {  // local ICP: match, fit, match again
      look_up([&](uint32_t v) { s.lanes[v] = motion_lanes(s.x[v], offset_of(v)); });
      ring_means(ring, s.lanes, s.spare_lanes, kMotionPasses, threads);
      parallel_for(n, threads, [&](uint32_t v) { s.motion[v] = fitted_motion(s.lanes[v], s.x[v]); });
    }
    look_up(match_only);
    const uint64_t covered = uint64_t(
        std::count_if(s.match.begin(), s.match.end(), [](uint32_t q) { return q != FrameMatcher::kNone; }));
    step.coverage = prior_coverage(covered, n);
    if (scene_cut(step.coverage)) {
      history.clear();
      ++history.resets;
      step.reset = true;
    } else {
      s.detail.resize(n);
      s.level.resize(n);
      parallel_for(n, threads, [&](uint32_t v) {
        const uint32_t q = s.match[v];
        s.detail[v] =
            q == FrameMatcher::kNone ? 0.f : prior_detail(s.x[v], s.motion[v], prior_at(q), normal_at(q));
        s.level[v] = s.detail[v] * s.detail[v];
      });
      ring_means(ring, s.level, s.spare_level, kAgreementPasses, threads);
      s.share.resize(n);
      parallel_for(n, threads, [&](uint32_t v) {
        const uint32_t q = s.match[v];
        s.share[v] = 0.f;
        if (q == FrameMatcher::kNone) return;
        s.share[v] = prior_share(s.level[v], strength, noise);
        const Vec3 move = (s.share[v] * s.detail[v] * float(mean_edge)) * normal_at(q);
        positions[3 * size_t(v)] += move.x;
        positions[3 * size_t(v) + 1] += move.y;
        positions[3 * size_t(v) + 2] += move.z;
      });
      double pulled = 0.0;
      for (uint32_t v = 0; v < n; ++v) pulled += s.share[v];  // in order: the report is reproducible
      step.share = float(pulled / n);
    }
  }
  keep_as_history(fan, n, positions, mean_edge, history, s, threads);
  if (follows && !step.reset) {  // the motion found, for the next frame's prediction
    history.motion.resize(3 * size_t(n));
    const float edge = float(mean_edge);
    parallel_for(n, threads, [&](uint32_t v) {
      const Vec3 m = edge * s.motion[v];
      history.motion[3 * size_t(v)] = m.x;
      history.motion[3 * size_t(v) + 1] = m.y;
      history.motion[3 * size_t(v) + 2] = m.z;
    });
  }
  return step;
}

}  // namespace fq
