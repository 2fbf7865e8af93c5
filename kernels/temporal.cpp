#include "kernels/temporal.h"

#include <algorithm>
#include <cmath>

#include "core/parallel_for.h"
#include "kernels/refine_math.h"
#include "kernels/temporal_math.h"
#include "kernels/vertex_faces.h"

namespace fq {

namespace {

/// `passes` ring means of `a` (kernels/refine_math.h), `spare` the other buffer.
template <class T>
void ring_means(const FanView& fan, std::vector<T>& a, std::vector<T>& spare, int passes, int threads) {
  spare.resize(a.size());
  for (int p = 0; p < passes; ++p) {
    parallel_for(static_cast<uint32_t>(a.size()), threads, [&](uint32_t v) { spare[v] = ring_mean(fan, a.data(), v); });
    a.swap(spare);
  }
}

/// Vertex -> incident triangles of the mesh, for the ring means.
FanView fan_of(const MeshView& mesh, TemporalScratch& s) {
  build_vertex_faces(mesh.triangles, mesh.num_triangles, mesh.num_vertices, s.vf_offsets, s.vf_faces);
  return FanView{mesh.triangles, s.vf_offsets.data(), s.vf_faces.data()};
}

Vec3 at(const float* xyz, uint32_t v) { return {xyz[3 * size_t(v)], xyz[3 * size_t(v) + 1], xyz[3 * size_t(v) + 2]}; }

}  // namespace

void vertex_normals(const MeshView& mesh, const float* xyz, std::vector<float>& out, int threads) {
  const uint32_t n = mesh.num_vertices;
  out.assign(3 * size_t(n), 0.f);
  // Serial accumulation: a parallel loop over triangles would race on shared vertices.
  for (uint32_t t = 0; t < mesh.num_triangles; ++t) {
    const uint32_t* tri = mesh.triangles + 3 * size_t(t);
    const Vec3 w = cross(at(xyz, tri[1]) - at(xyz, tri[0]), at(xyz, tri[2]) - at(xyz, tri[0]));
    for (int k = 0; k < 3; ++k) {
      float* o = &out[3 * size_t(tri[k])];
      o[0] += w.x;
      o[1] += w.y;
      o[2] += w.z;
    }
  }
  parallel_for(n, threads, [&](uint32_t v) {
    const Vec3 u = normalized_or_zero(at(out.data(), v));
    out[3 * size_t(v)] = u.x;
    out[3 * size_t(v) + 1] = u.y;
    out[3 * size_t(v) + 2] = u.z;
  });
}

TemporalStep follow_history(const MeshView& mesh, std::vector<float>& positions, double mean_edge, float noise,
                            float strength, TemporalHistory& history, TemporalScratch& s, int threads) {
  const uint32_t n = mesh.num_vertices;
  TemporalStep step;
  if (!history.empty() && n > 0 && mean_edge > 0.0) {
    // The math runs in mean edges about the first vertex (floats keep their precision there).
    const Vec3 origin = at(positions.data(), 0);
    const float unit = float(1.0 / mean_edge);
    const auto normalized = [&](const float* p) { return unit * (Vec3{p[0], p[1], p[2]} - origin); };
    const auto prior_at = [&](uint32_t q) { return normalized(&history.positions[3 * size_t(q)]); };
    const auto normal_at = [&](uint32_t q) { return at(history.normals.data(), q); };
    const FanView fan = fan_of(mesh, s);
    s.x.resize(n);
    parallel_for(n, threads, [&](uint32_t v) { s.x[v] = normalized(&positions[3 * size_t(v)]); });
    s.motion.assign(n, Vec3{0.f, 0.f, 0.f});
    s.offset.resize(n);
    s.match.resize(n);
    const float reach = float(kPriorReach * mean_edge);  // input units, as the index
    // Each lookup from the last motion estimate; a vertex that finds none counts as no motion.
    const auto look_up = [&] {
      parallel_for(n, threads, [&](uint32_t v) {
        const Vec3 q = origin + float(mean_edge) * (s.x[v] + s.motion[v]);
        s.match[v] = history.index.nearest(q, reach);
        s.offset[v] = s.match[v] == NearestVertexIndex::kNone ? Vec3{0.f, 0.f, 0.f} : prior_at(s.match[v]) - s.x[v];
      });
    };
    for (int it = 0; it < kMotionIterations; ++it) {
      look_up();
      s.motion = s.offset;
      ring_means(fan, s.motion, s.spare, kMotionPasses, threads);
    }
    look_up();
    const uint64_t covered = uint64_t(std::count_if(s.match.begin(), s.match.end(),
                                                    [](uint32_t q) { return q != NearestVertexIndex::kNone; }));
    step.coverage = float(double(covered) / n);
    if (step.coverage < kMinPriorCoverage) {
      history.clear();
      ++history.resets;
      step.reset = true;
    } else {
      s.detail.resize(n);
      s.level.resize(n);
      parallel_for(n, threads, [&](uint32_t v) {
        const uint32_t q = s.match[v];
        s.detail[v] = q == NearestVertexIndex::kNone ? 0.f : prior_detail(s.x[v], s.motion[v], prior_at(q), normal_at(q));
        s.level[v] = s.detail[v] * s.detail[v];
      });
      ring_means(fan, s.level, s.spare_level, kAgreementPasses, threads);
      const float tolerance = kPriorTolerance * noise;
      double pulled = 0.0;
      for (uint32_t v = 0; v < n; ++v) {  // serial: the sum, and so the report, is reproducible
        const uint32_t q = s.match[v];
        if (q == NearestVertexIndex::kNone) continue;
        const float share = strength * prior_agreement(s.level[v], tolerance);
        const Vec3 move = (share * s.detail[v] * float(mean_edge)) * normal_at(q);
        positions[3 * size_t(v)] += move.x;
        positions[3 * size_t(v) + 1] += move.y;
        positions[3 * size_t(v) + 2] += move.z;
        pulled += share;
      }
      step.share = float(pulled / n);
    }
  }
  vertex_normals(mesh, positions.data(), s.normals, threads);
  history.positions.assign(positions.begin(), positions.begin() + 3 * size_t(n));
  history.normals.swap(s.normals);
  history.index.build(history.positions.data(), n, float(mean_edge));
  ++history.frames;
  return step;
}

}  // namespace fq
