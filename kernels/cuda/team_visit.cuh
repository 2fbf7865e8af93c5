// A team of T lanes of one warp per vertex for the neighbourhood passes: the lanes share
// one vertex's candidate rows (exactly the rows of grid.h's for_each_neighbor) and take
// the candidates of each row round-robin, then combine their partial sums by shuffles.
// T lanes per vertex multiply the threads in flight by T (small meshes fill the GPU) and
// make the row loop uniform across the team.
#pragma once

#include <cstdint>

#include "kernels/cuda/packed_quadric.cuh"
#include "kernels/filter_math.h"
#include "kernels/grid.h"
#include "kernels/quadric.h"
#include "kernels/vec3.h"

namespace fq::cuda {

/// Calls f(j, point_j, d = point_j - p, |d|^2) for this lane's share of the points within
/// `radius` of p: the same rows and cells as for_each_neighbor, and within a row the
/// candidates j = begin + lane, begin + lane + T, ... (so each lane sees increasing j).
template <int T, class F>
__device__ void team_for_each_neighbor(const GridView& g, Vec3 p, float radius, unsigned lane, F&& f) {
  const float r2 = radius * radius;
  for_each_candidate_run(g, p, radius, [&](uint32_t begin, uint32_t end) {
    for (uint32_t j = begin + lane; j < end; j += T) {
      const Point4 q = load_point(g.points, j);
      const Vec3 d{q.x - p.x, q.y - p.y, q.z - p.z};
      const float d2 = norm2(d);
      if (d2 <= r2) f(j, q, d, d2);
    }
  });
}

/// Sum over the team (every lane gets it). All 32 lanes of the warp must call it.
template <int T>
__device__ float team_sum(float v) {
#pragma unroll
  for (int o = T / 2; o > 0; o /= 2) v += __shfl_xor_sync(0xffffffffu, v, o, T);
  return v;
}

template <int T>
__device__ void team_sum(QuadricSum& s) {
  Quadric& q = s.q;
  s.w = team_sum<T>(s.w);
  q.a00 = team_sum<T>(q.a00);
  q.a01 = team_sum<T>(q.a01);
  q.a02 = team_sum<T>(q.a02);
  q.a11 = team_sum<T>(q.a11);
  q.a12 = team_sum<T>(q.a12);
  q.a22 = team_sum<T>(q.a22);
  q.b0 = team_sum<T>(q.b0);
  q.b1 = team_sum<T>(q.b1);
  q.b2 = team_sum<T>(q.b2);
  q.c = team_sum<T>(q.c);
}

/// The team's best (p, j): the largest p, and among equal positive p the smallest j --
/// what a single thread visiting j in increasing order with `if (p > pmax)` keeps.
template <int T>
__device__ void team_argmax(float& p, uint32_t& j) {
#pragma unroll
  for (int o = T / 2; o > 0; o /= 2) {
    const float op = __shfl_xor_sync(0xffffffffu, p, o, T);
    const uint32_t oj = __shfl_xor_sync(0xffffffffu, j, o, T);
    if (op > p || (op == p && op > 0.f && oj < j)) {
      p = op;
      j = oj;
    }
  }
}

}  // namespace fq::cuda
