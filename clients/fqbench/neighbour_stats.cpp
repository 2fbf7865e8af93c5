#include "clients/fqbench/neighbour_stats.h"

#include <vector>

#include "core/parallel_for.h"
#include "kernels/frame_plan.h"
#include "kernels/frame_prep.h"
#include "kernels/grid_build.h"

namespace fq::bench {

namespace {

double mean_count(const GridView& g, float radius) {
  std::vector<uint32_t> count(g.count);
  parallel_for(g.count, hardware_threads(), [&](uint32_t i) {
    uint32_t c = 0;
    for_each_neighbor(g, xyz(g.points[i]), radius, [&](uint32_t, const Point4&, Vec3, float) { ++c; });
    count[i] = c;
  });
  double sum = 0.0;
  for (uint32_t c : count) sum += c;
  return g.count ? sum / g.count : 0.0;
}

}  // namespace

NeighbourStats neighbour_stats(const MeshView& mesh, const Params& params) {
  NeighbourStats out;
  Normalization norm;
  if (!compute_normalization(mesh, norm).ok()) return out;
  std::vector<Vec3> p(mesh.num_vertices);
  for (uint32_t i = 0; i < mesh.num_vertices; ++i) p[i] = norm.to_normalized(mesh.positions + 3 * size_t(i));
  // The frame's own run (the first of its plan): its grid, its radii.
  const RunPlan run = plan_frame(params).runs.front();
  CpuGrid grid;
  build_grid(p.data(), mesh.num_vertices, run.grid_cell, grid);
  std::vector<Point4> sorted(mesh.num_vertices);
  for (uint32_t k = 0; k < mesh.num_vertices; ++k) {
    const Vec3 q = p[grid.order[k]];
    sorted[k] = {q.x, q.y, q.z, 0.f};
  }
  const GridView g = grid.view(sorted.data());
  out.nbhd = mean_count(g, run.sigma_b.radius);
  out.diffusion = mean_count(g, run.sigma_s.radius);
  if (params.cluster) out.cluster = mean_count(g, run.sigma_d.radius);
  return out;
}

}  // namespace fq::bench
