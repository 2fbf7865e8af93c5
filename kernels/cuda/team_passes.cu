// The neighbourhood passes with a team of T lanes per vertex (team_visit.cuh). Each lane
// adds its share of the neighbours with the very term functions the CPU engine uses
// (filter_math.h, cluster_math.h); the lanes' partial sums are combined by shuffles, so
// the summation order (not the neighbour set or the math) differs from the CPU; link keeps
// the CPU's tie-break exactly.
#include <type_traits>

#include "kernels/cluster_math.h"
#include "kernels/cuda/launch.cuh"
#include "kernels/cuda/team_passes.cuh"
#include "kernels/cuda/team_visit.cuh"
#include "kernels/filter_math.h"
#include "kernels/gaussian.h"

// Occupancy experiment (docs/BENCHMARKS.md): build with -DFQ_TEAM_MIN_BLOCKS=6 to cap the
// team kernels at 40 registers (6 blocks of tuning::kItemBlock per SM); 0 leaves the
// compiler's choice.
#ifndef FQ_TEAM_MIN_BLOCKS
#define FQ_TEAM_MIN_BLOCKS 0
#endif
#if FQ_TEAM_MIN_BLOCKS > 0
#define FQ_TEAM_BOUNDS __launch_bounds__(tuning::kItemBlock, FQ_TEAM_MIN_BLOCKS)
#else
#define FQ_TEAM_BOUNDS
#endif

namespace fq::cuda {

namespace {

// Gaussian weight: gaussian.h's accurate exp, or with `fast` the hardware approximation
// __expf (relative error ~1e-6 here, far inside the parity tolerance). Measured in
// docs/BENCHMARKS.md; CudaTuning::fast_exp selects it.
struct Weight {
  Gaussian g;
  bool fast;
  __device__ float of_squared(float x2) const {
    return fast ? __expf(x2 * g.neg_inv_two_sigma2) : g.of_squared(x2);
  }
};

struct Slot {
  uint32_t i;     ///< vertex (grid order)
  unsigned lane;  ///< lane within the team
  bool active;    ///< i < count (inactive lanes still join the shuffles)
};

template <int T>
__device__ Slot slot_of(uint32_t count) {
  const uint64_t t = item_index();
  const uint32_t i = static_cast<uint32_t>(t / T);
  return {i, static_cast<unsigned>(t % T), i < count};
}

// filter_math.h neighbourhood_quadric
template <int T>
__global__ void FQ_TEAM_BOUNDS team_neighbourhood(GridView g, const PackedQuadric* base, Weight gb,
                                                  float radius, PackedQuadric* out) {
  const Slot s = slot_of<T>(g.count);
  QuadricSum acc = zero_quadric_sum();
  if (s.active) {
    team_for_each_neighbor<T>(g, xyz(g.points[s.i]), radius, s.lane,
                              [&](uint32_t j, const Point4& pj, Vec3 d, float d2) {
                                add_neighbourhood_term(acc, load_quadric(base, j), pj, d, d2, gb);
                              });
  }
  team_sum<T>(acc);
  if (!s.active || s.lane != 0) return;
  out[s.i] = pack(mean_of(acc));
}

// filter_math.h bilateral_quadric
template <int T>
__global__ void FQ_TEAM_BOUNDS team_diffusion(GridView g, const PackedQuadric* nbhd, Weight gs, Weight gr,
                                              float radius, Quadric* out, PackedQuadric* out_p) {
  const Slot s = slot_of<T>(g.count);
  QuadricSum acc = zero_quadric_sum();
  if (s.active) {
    team_for_each_neighbor<T>(g, xyz(g.points[s.i]), radius, s.lane,
                              [&](uint32_t j, const Point4& pj, Vec3 d, float d2) {
                                add_bilateral_term(acc, load_quadric(nbhd, j), pj, d, d2, gs, gr);
                              });
  }
  team_sum<T>(acc);
  if (!s.active || s.lane != 0) return;
  const Quadric q = mean_of(acc);
  out[s.i] = q;
  out_p[s.i] = pack(q);
}

// cluster_math.h representativity
template <int T>
__global__ void FQ_TEAM_BOUNDS team_score(GridView g, const Quadric* qbl, Weight gd, Weight gq, float radius,
                                          bool euclid, float* score) {
  const Slot s = slot_of<T>(g.count);
  ScoreSum acc{0.f, 0.f};
  if (s.active) {
    const Quadric qi = qbl[s.i];
    team_for_each_neighbor<T>(g, xyz(g.points[s.i]), radius, s.lane,
                              [&](uint32_t, const Point4& pj, Vec3 d, float d2) {
                                add_score_term(acc, qi, pj, d, d2, gd, gq, euclid);
                              });
  }
  acc.num = team_sum<T>(acc.num);
  acc.den = team_sum<T>(acc.den);
  if (s.active && s.lane == 0) score[s.i] = score_of(acc);
}

// cluster_math.h quick_shift_link
template <int T>
__global__ void FQ_TEAM_BOUNDS team_link(GridView g, const PackedQuadric* qbl, const float* score, Weight gd,
                                         Weight gq, float radius, bool euclid, float cut, uint32_t* next) {
  const Slot s = slot_of<T>(g.count);
  LinkBest best{0.f, s.i};
  if (s.active) {
    const float si = score[s.i];
    team_for_each_neighbor<T>(g, xyz(g.points[s.i]), radius, s.lane,
                              [&](uint32_t j, const Point4&, Vec3 d, float d2) {
                                if (j == s.i || !ranks_above(score[j], j, si, s.i)) return;
                                best.offer(link_proximity(load_quadric(qbl, j), d, d2, gd, gq, euclid), j);
                              });
  }
  team_argmax<T>(best.p, best.j);
  if (s.active && s.lane == 0) next[s.i] = best.target(s.i, cut);
}

/// Calls launch(std::integral_constant<int, T>{}) for the supported team size T that is
/// `team` (32 for any other value): each kernel is instantiated once per size.
template <class Launch>
void with_team_size(int team, Launch&& launch) {
  switch (team) {
    case 1:
      return launch(std::integral_constant<int, 1>{});
    case 2:
      return launch(std::integral_constant<int, 2>{});
    case 4:
      return launch(std::integral_constant<int, 4>{});
    case 8:
      return launch(std::integral_constant<int, 8>{});
    case 16:
      return launch(std::integral_constant<int, 16>{});
    default:
      return launch(std::integral_constant<int, 32>{});
  }
}

// Launches `kernel` instantiated for the team size asked for, team_blocks() blocks of
// block_size() threads.
#define FQ_TEAM_LAUNCH(kernel, team, n, s, ...)                                          \
  with_team_size(team, [&](auto size) {                                                  \
    constexpr int T = decltype(size)::value;                                             \
    FQ_LAUNCH(kernel<T>, launch_shape(team_blocks(n, T), block_size()), s, __VA_ARGS__); \
  })

}  // namespace

void team_neighbourhood_quadrics(DeviceFrame& f, Extent sigma_b, int team, bool fast_exp, cudaStream_t s) {
  const GridView g = f.grid.view(f.points.data());
  FQ_TEAM_LAUNCH(team_neighbourhood, team, f.n, s, g, f.base_p.data(),
                 Weight{Gaussian::with_sigma(sigma_b.sigma), fast_exp}, sigma_b.radius,
                 f.nbhd_p.reserve(f.n));
}

void team_diffuse_quadrics(DeviceFrame& f, const RunPlan& run, int team, bool fast_exp, cudaStream_t s) {
  const GridView g = f.grid.view(f.points.data());
  FQ_TEAM_LAUNCH(team_diffusion, team, f.n, s, g, f.nbhd_p.data(),
                 Weight{Gaussian::with_sigma(run.sigma_s.sigma), fast_exp},
                 Weight{Gaussian::with_sigma(run.sigma_r), fast_exp}, run.sigma_s.radius, f.bl.reserve(f.n),
                 f.bl_p.reserve(f.n));
}

void team_cluster_scores(DeviceFrame& f, const RunPlan& run, int team, bool fast_exp, cudaStream_t s) {
  const GridView g = f.grid.view(f.points.data());
  FQ_TEAM_LAUNCH(team_score, team, f.n, s, g, f.bl.data(),
                 Weight{Gaussian::with_sigma(run.sigma_d.sigma), fast_exp},
                 Weight{Gaussian::with_sigma(run.sigma_q), fast_exp}, run.sigma_d.radius,
                 run.params.clustering.method == ClusterMethod::kEuclidean, f.score.reserve(f.n));
}

void team_cluster_links(DeviceFrame& f, const RunPlan& run, int team, bool fast_exp, cudaStream_t s) {
  const GridView g = f.grid.view(f.points.data());
  const ClusterParams& p = run.params.clustering;
  FQ_TEAM_LAUNCH(team_link, team, f.n, s, g, f.bl_p.data(), f.score.data(),
                 Weight{Gaussian::with_sigma(run.sigma_d.sigma), fast_exp},
                 Weight{Gaussian::with_sigma(run.sigma_q), fast_exp}, run.sigma_d.radius,
                 p.method == ClusterMethod::kEuclidean, 1.0f - p.theta, f.next.reserve(f.n));
}

}  // namespace fq::cuda
