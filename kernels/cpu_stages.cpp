#include "kernels/cpu_stages.h"

#include <algorithm>
#include <cmath>

#include "core/parallel_for.h"
#include "kernels/bilateral_math.h"
#include "kernels/cluster_math.h"
#include "kernels/filter_math.h"
#include "kernels/gaussian.h"
#include "kernels/link_export.h"
#include "kernels/refine_math.h"
#include "kernels/refine_plan.h"
#include "kernels/vertex_faces.h"

namespace fq::cpu {

void sort_into_grid(const MeshView& mesh, float cell, CpuFrame& f) {
  const uint32_t n = mesh.num_vertices, m = mesh.num_triangles;
  f.normalized.resize(n);
  for (uint32_t i = 0; i < n; ++i) f.normalized[i] = f.norm.to_normalized(mesh.positions + 3 * size_t(i));
  build_grid(f.normalized.data(), n, cell, f.grid);
  f.rank.resize(n);
  f.points.resize(n);
  for (uint32_t k = 0; k < n; ++k) {
    const uint32_t i = f.grid.order[k];
    f.rank[i] = k;
    const Vec3 p = f.normalized[i];
    f.points[k] = {p.x, p.y, p.z, 0.f};
  }
  f.tris.resize(3 * size_t(m));
  for (size_t t = 0; t < 3 * size_t(m); ++t) f.tris[t] = f.rank[mesh.triangles[t]];
}

void base_quadrics(CpuFrame& f, int threads) {
  const uint32_t n = static_cast<uint32_t>(f.points.size());
  const uint32_t m = static_cast<uint32_t>(f.tris.size() / 3);
  f.tri_geom.resize(m);
  parallel_for(m, threads, [&](uint32_t t) {
    const uint32_t* tri = &f.tris[3 * size_t(t)];
    f.tri_geom[t] = triangle_geom(xyz(f.points[tri[0]]), xyz(f.points[tri[1]]), xyz(f.points[tri[2]]));
  });
  build_vertex_faces(f.tris.data(), f.tris.size() / 3, n, f.vf_offsets, f.vf_faces);
  f.base.resize(n);
  f.vnormal.resize(n);
  parallel_for(n, threads, [&](uint32_t v) {
    const Vec3 x = xyz(f.points[v]);
    VertexAccum acc = zero_vertex_accum();
    for (uint32_t k = f.vf_offsets[v]; k < f.vf_offsets[v + 1]; ++k)
      add_triangle(acc, f.tri_geom[f.vf_faces[k]], x);
    f.base[v] = base_quadric(acc);
    f.points[v].w = acc.area;
    f.vnormal[v] = acc.normal;
  });
}

void neighbourhood_quadrics(CpuFrame& f, Extent sigma_b, int threads) {
  const GridView g = f.grid.view(f.points.data());
  const Gaussian gb = Gaussian::with_sigma(sigma_b.sigma);
  f.nbhd.resize(g.count);
  parallel_for(g.count, threads, [&](uint32_t i) {
    f.nbhd[i] = neighbourhood_quadric(g, f.base.data(), i, gb, sigma_b.radius);
  });
}

void diffuse_quadrics(CpuFrame& f, const RunPlan& run, int threads) {
  const GridView g = f.grid.view(f.points.data());
  const Gaussian gs = Gaussian::with_sigma(run.sigma_s.sigma), gr = Gaussian::with_sigma(run.sigma_r);
  f.bl.resize(g.count);
  parallel_for(g.count, threads, [&](uint32_t i) {
    f.bl[i] = bilateral_quadric(g, f.nbhd.data(), i, gs, gr, run.sigma_s.radius);
  });
}

void update_positions(CpuFrame& f, const RunPlan& run, int threads) {
  const GridView g = f.grid.view(f.points.data());
  const FilterParams& p = run.params.filtering;
  const Gaussian gn = Gaussian::with_sigma(run.sigma_n.sigma);
  f.moved.resize(g.count);
  parallel_for(g.count, threads, [&](uint32_t i) {
    const Vec3 n =
        p.constrained ? smoothed_normal(g, f.vnormal.data(), i, gn, run.sigma_n.radius) : Vec3{0, 0, 0};
    f.moved[i] = updated_position(xyz(f.points[i]), f.bl[i], p.constrained, n, p.tikhonov);
  });
}

NoiseEstimate estimate_noise(CpuFrame& f, int threads) {
  const uint32_t n = static_cast<uint32_t>(f.points.size());
  const FanView fan{f.tris.data(), f.vf_offsets.data(), f.vf_faces.data()};
  // The samples read positions as Vec3: the input's, where refine_positions starts.
  f.moved.resize(n);
  parallel_for(n, threads, [&](uint32_t v) { f.moved[v] = xyz(f.points[v]); });
  const uint32_t stride = noise_sample_stride(n), count = noise_sample_count(n);
  f.noise_samples.resize(count);
  parallel_for(count, threads,
               [&](uint32_t k) { f.noise_samples[k] = noise_sample(fan, f.moved.data(), k * stride); });
  return estimate_noise(f.noise_samples.data(), count);
}

void refine_positions(CpuFrame& f, const RefinePlan& plan, int threads) {
  const uint32_t n = static_cast<uint32_t>(f.points.size());
  const uint32_t m = static_cast<uint32_t>(f.tris.size() / 3);
  const FanView fan{f.tris.data(), f.vf_offsets.data(), f.vf_faces.data()};
  f.refine_x.resize(n);
  f.refine_closed.resize(n);
  parallel_for(n, threads, [&](uint32_t v) { f.refine_closed[v] = closed_fan(fan, v) ? 1 : 0; });
  f.refine_geom.resize(m);
  f.refine_n[0].resize(m);
  f.refine_n[1].resize(m);
  f.refine_free.resize(n);
  const Passes rounds = plan.rounds, normals = plan.normal_passes, updates = plan.vertex_passes;
  for (int round = 0; round < rounds.count; ++round) {
    const float round_share = round == rounds.count - 1 ? rounds.last : 1.f;
    if (round_share < 1.f) f.refine_round = f.moved;
    parallel_for(m, threads, [&](uint32_t t) {
      const uint32_t* tri = &f.tris[3 * size_t(t)];
      f.refine_geom[t] = triangle_geom(f.moved[tri[0]], f.moved[tri[1]], f.moved[tri[2]]);
      f.refine_n[0][t] = f.refine_geom[t].normal;
    });
    for (int it = 0; it < normals.count; ++it) {
      const Vec3* in = f.refine_n[it & 1].data();
      Vec3* out = f.refine_n[(it + 1) & 1].data();
      const float share = it == normals.count - 1 ? normals.last : 1.f;
      parallel_for(m, threads, [&](uint32_t t) {
        out[t] = partial_normal(
            in[t], filtered_face_normal(fan, f.refine_geom.data(), in, t, plan.gs, plan.gr), share);
      });
    }
    const Vec3* filtered = f.refine_n[normals.count & 1].data();
    parallel_for(n, threads, [&](uint32_t v) {
      f.refine_free[v] = free_directions(fan, filtered, v, f.refine_closed[v] != 0);
    });
    for (int it = 0; it < updates.count; ++it) {
      const float share = it == updates.count - 1 ? updates.last : 1.f;
      parallel_for(n, threads, [&](uint32_t v) {
        const Vec3 next =
            updated_vertex(fan, f.moved.data(), filtered, v, f.refine_free[v], plan.tangential_step);
        f.refine_x[v] = partial_position(f.moved[v], next, share);
      });
      f.moved.swap(f.refine_x);
    }
    if (round_share < 1.f)
      parallel_for(n, threads, [&](uint32_t v) {
        f.moved[v] = partial_position(f.refine_round[v], f.moved[v], round_share);
      });
  }
  // Step 3: tangential moves cut back to what the noise explains.
  f.refine_t.resize(n);
  f.refine_e[0].resize(n);
  f.refine_e[1].resize(n);
  parallel_for(n, threads, [&](uint32_t v) {
    const Vec3 normal = vertex_normal(fan, f.moved.data(), v);
    f.refine_t[v] = tangential_move(xyz(f.points[v]), f.moved[v], normal);
    f.refine_e[0][v] =
        slide_level(fan, f.points.data(), f.moved.data(), v, f.refine_t[v], normal, plan.noise_direction);
  });
  for (int pass = 0; pass < kEnergyPasses; ++pass) {
    const SlideLevel* in = f.refine_e[pass & 1].data();
    SlideLevel* out = f.refine_e[(pass + 1) & 1].data();
    parallel_for(n, threads, [&](uint32_t v) { out[v] = ring_mean(fan, in, v); });
  }
  const SlideLevel* level = f.refine_e[kEnergyPasses & 1].data();
  parallel_for(n, threads, [&](uint32_t v) {
    f.moved[v] =
        limited_position(f.moved[v], f.refine_t[v], level[v].energy,
                         slide_allowance(level[v], plan.tangential_allowance, plan.directional_allowance));
  });
}

void bilateral_filter(CpuFrame& f, const RunPlan& run, int threads) {
  const uint32_t m = static_cast<uint32_t>(f.tri_geom.size());
  std::vector<Vec3> centroids(m);
  for (uint32_t t = 0; t < m; ++t) centroids[t] = f.tri_geom[t].centroid;
  build_grid(centroids.data(), m, run.grid_cell, f.tri_grid);
  f.tri_points.resize(m);
  f.tri_normals.resize(m);
  for (uint32_t k = 0; k < m; ++k) {
    const TriangleGeom& t = f.tri_geom[f.tri_grid.order[k]];
    f.tri_points[k] = {t.centroid.x, t.centroid.y, t.centroid.z, t.area};
    f.tri_normals[k] = t.normal;
  }
  const GridView tg = f.tri_grid.view(f.tri_points.data());
  const Gaussian gm = Gaussian::with_sigma(run.mollify.sigma);
  f.tri_mollified.resize(m);
  parallel_for(m, threads, [&](uint32_t t) {
    f.tri_mollified[t] = mollified_face_normal(tg, f.tri_normals.data(), t, gm, run.mollify.radius);
  });
  const Gaussian gs = Gaussian::with_sigma(run.sigma_s.sigma), gr = Gaussian::with_sigma(run.sigma_r);
  f.moved.resize(f.points.size());
  parallel_for(static_cast<uint32_t>(f.points.size()), threads, [&](uint32_t i) {
    f.moved[i] =
        jones_bilateral_position(tg, f.tri_mollified.data(), xyz(f.points[i]), gs, gr, run.sigma_s.radius);
  });
}

void cluster_scores(CpuFrame& f, const RunPlan& run, int threads) {
  const GridView g = f.grid.view(f.points.data());
  const Gaussian gd = Gaussian::with_sigma(run.sigma_d.sigma), gq = Gaussian::with_sigma(run.sigma_q);
  const bool euclid = run.params.clustering.method == ClusterMethod::kEuclidean;
  f.score.resize(g.count);
  parallel_for(g.count, threads, [&](uint32_t i) {
    f.score[i] = representativity(g, f.bl.data(), i, gd, gq, run.sigma_d.radius, euclid);
  });
}

void cluster_links(CpuFrame& f, const RunPlan& run, int threads) {
  const GridView g = f.grid.view(f.points.data());
  const Gaussian gd = Gaussian::with_sigma(run.sigma_d.sigma), gq = Gaussian::with_sigma(run.sigma_q);
  const bool euclid = run.params.clustering.method == ClusterMethod::kEuclidean;
  const float cut = 1.0f - run.params.clustering.theta;
  f.next.resize(g.count);
  parallel_for(g.count, threads, [&](uint32_t i) {
    f.next[i] = quick_shift_link(g, f.bl.data(), f.score.data(), i, gd, gq, run.sigma_d.radius, euclid, cut);
  });
}

uint32_t cluster_labels(CpuFrame& f, std::vector<uint32_t>& labels, int threads) {
  const uint32_t n = static_cast<uint32_t>(f.next.size());
  std::vector<uint32_t> roots;
  for (uint32_t k = 0; k < n; ++k) {
    if (f.next[k] == k) roots.push_back(k);
  }
  std::sort(roots.begin(), roots.end(),
            [&](uint32_t a, uint32_t b) { return f.grid.order[a] < f.grid.order[b]; });
  std::vector<uint32_t> label_of(n, 0);
  for (uint32_t r = 0; r < roots.size(); ++r) label_of[roots[r]] = r;
  labels.resize(n);
  parallel_for(n, threads, [&](uint32_t i) { labels[i] = label_of[find_root(f.next.data(), f.rank[i])]; });
  return static_cast<uint32_t>(roots.size());
}

void export_links(const CpuFrame& f, const ClusterParams& p, std::vector<uint32_t>& parent,
                  std::vector<float>& prox, int threads) {
  const uint32_t n = static_cast<uint32_t>(f.next.size());
  const Gaussian gd = Gaussian::with_sigma(p.sigma_d), gq = Gaussian::with_sigma(p.sigma_q);
  parent.resize(n);
  prox.resize(n);
  parallel_for(n, threads, [&](uint32_t i) {
    export_link(f.points.data(), f.bl.data(), f.next.data(), f.grid.order.data(), f.rank[i], gd, gq,
                p.method == ClusterMethod::kEuclidean, parent[i], prox[i]);
  });
}

}  // namespace fq::cpu
