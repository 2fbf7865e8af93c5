// The neighbourhood passes with a team of T lanes per vertex (team_visit.cuh). Each body
// is the per-neighbour term of the CPU function named beside it, built from the same
// quadric.h / gaussian.h / cluster_math.h primitives; the parity tests hold the two paths
// to the CPU engine. Partial sums are combined by shuffles, so summation order (not the
// neighbour set) differs from the CPU; link keeps the CPU's tie-break exactly.
#include "cluster_math.h"
#include "cuda_check.cuh"
#include "gaussian.h"
#include "launch.cuh"
#include "team_passes.cuh"
#include "team_visit.cuh"

// Occupancy experiment (docs/BENCHMARKS.md): build with -DFQ_TEAM_MIN_BLOCKS=6 to cap the
// team kernels at 40 registers (6 blocks of 256 per SM); 0 leaves the compiler's choice.
#ifndef FQ_TEAM_MIN_BLOCKS
#define FQ_TEAM_MIN_BLOCKS 0
#endif
#if FQ_TEAM_MIN_BLOCKS > 0
#define FQ_TEAM_BOUNDS __launch_bounds__(256, FQ_TEAM_MIN_BLOCKS)
#else
#define FQ_TEAM_BOUNDS
#endif

namespace fq::cuda {

namespace {

// The weighted sum over its weight sum, component by component (quadric.h divide(), which
// the CPU functions use: stays finite when the weight sum is denormal).
__device__ void normalize_sum(Quadric& q, float wsum) {
  q.a00 /= wsum;
  q.a01 /= wsum;
  q.a02 /= wsum;
  q.a11 /= wsum;
  q.a12 /= wsum;
  q.a22 /= wsum;
  q.b0 /= wsum;
  q.b1 /= wsum;
  q.b2 /= wsum;
  q.c /= wsum;
}

// Gaussian weight: gaussian.h's accurate exp, or with `fast` the hardware approximation
// __expf (relative error ~1e-6 here, far inside the parity tolerance). Measured in
// docs/BENCHMARKS.md; FQ_CUDA_FAST_EXP selects it.
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
  const uint64_t t = uint64_t(blockIdx.x) * blockDim.x + threadIdx.x;
  const uint32_t i = static_cast<uint32_t>(t / T);
  return {i, static_cast<unsigned>(t % T), i < count};
}

// filter_math.h neighbourhood_quadric
template <int T>
__global__ void FQ_TEAM_BOUNDS team_neighbourhood(GridView g, const PackedQuadric* base, Weight gb,
                                                  float radius, PackedQuadric* out) {
  const Slot s = slot_of<T>(g.count);
  Quadric acc = zero_quadric();
  float wsum = 0.f;
  if (s.active) {
    team_for_each_neighbor<T>(g, xyz(g.points[s.i]), radius, s.lane,
                              [&](uint32_t j, const Point4& pj, Vec3 d, float d2) {
                                const float w = pj.w * gb.of_squared(d2);
                                if (!(w > 0.f)) return;
                                const Vec3 t = -1.0f * d;
                                const Quadric qj = load_quadric(base, j);
                                add_translated(acc, qj, t, evaluate(qj, t), w);
                                wsum += w;
                              });
  }
  team_sum<T>(acc);
  wsum = team_sum<T>(wsum);
  if (!s.active || s.lane != 0) return;
  if (wsum > 0.f) normalize_sum(acc, wsum);
  out[s.i] = pack(acc);
}

// filter_math.h bilateral_quadric
template <int T>
__global__ void FQ_TEAM_BOUNDS team_diffusion(GridView g, const PackedQuadric* nbhd, Weight gs, Weight gr,
                                              float radius, Quadric* out, PackedQuadric* out_p) {
  const Slot s = slot_of<T>(g.count);
  Quadric acc = zero_quadric();
  float wsum = 0.f;
  if (s.active) {
    team_for_each_neighbor<T>(g, xyz(g.points[s.i]), radius, s.lane,
                              [&](uint32_t j, const Point4& pj, Vec3 d, float d2) {
                                const Vec3 t = -1.0f * d;
                                const Quadric qj = load_quadric(nbhd, j);
                                const float e = evaluate(qj, t);
                                const float w = pj.w * gs.of_squared(d2) * gr.of_squared(e);
                                if (!(w > 0.f)) return;
                                add_translated(acc, qj, t, e, w);
                                wsum += w;
                              });
  }
  team_sum<T>(acc);
  wsum = team_sum<T>(wsum);
  if (!s.active || s.lane != 0) return;
  if (wsum > 0.f) normalize_sum(acc, wsum);
  out[s.i] = acc;
  out_p[s.i] = pack(acc);
}

// cluster_math.h representativity
template <int T>
__global__ void FQ_TEAM_BOUNDS team_score(GridView g, const Quadric* qbl, Weight gd, Weight gq, float radius,
                                          bool euclid, float* score) {
  const Slot s = slot_of<T>(g.count);
  float num = 0.f, den = 0.f;
  if (s.active) {
    const Quadric qi = qbl[s.i];
    team_for_each_neighbor<T>(g, xyz(g.points[s.i]), radius, s.lane,
                              [&](uint32_t, const Point4& pj, Vec3 d, float d2) {
                                den += pj.w;
                                float w = pj.w * gd.of_squared(d2);
                                if (!euclid) w *= gq.of_squared(evaluate(qi, d));
                                num += w;
                              });
  }
  num = team_sum<T>(num);
  den = team_sum<T>(den);
  if (s.active && s.lane == 0) score[s.i] = den > 0.f ? num / den : 0.f;
}

// cluster_math.h quick_shift_link
template <int T>
__global__ void FQ_TEAM_BOUNDS team_link(GridView g, const PackedQuadric* qbl, const float* score, Weight gd,
                                         Weight gq, float radius, bool euclid, float cut, uint32_t* next) {
  const Slot s = slot_of<T>(g.count);
  float pmax = 0.f;
  uint32_t best = s.i;
  if (s.active) {
    const float si = score[s.i];
    team_for_each_neighbor<T>(g, xyz(g.points[s.i]), radius, s.lane,
                              [&](uint32_t j, const Point4&, Vec3 d, float d2) {
                                if (j == s.i || !ranks_above(score[j], j, si, s.i)) return;
                                float p = gd.of_squared(d2);
                                if (!euclid) p *= gq.of_squared(evaluate(load_quadric(qbl, j), -1.0f * d));
                                if (p > pmax) {
                                  pmax = p;
                                  best = j;
                                }
                              });
  }
  team_argmax<T>(pmax, best);
  if (s.active && s.lane == 0) next[s.i] = pmax < cut ? s.i : best;
}

unsigned team_blocks(uint32_t n, int team) { return blocks_for(uint64_t(n) * team); }

// Instantiates `kernel` for the supported team sizes and launches the one asked for.
#define FQ_TEAM_LAUNCH(kernel, team, n, s, ...)                              \
  do {                                                                       \
    switch (team) {                                                          \
      case 1:                                                                \
        kernel<1><<<team_blocks(n, 1), block_size(), 0, s>>>(__VA_ARGS__);   \
        break;                                                               \
      case 2:                                                                \
        kernel<2><<<team_blocks(n, 2), block_size(), 0, s>>>(__VA_ARGS__);   \
        break;                                                               \
      case 4:                                                                \
        kernel<4><<<team_blocks(n, 4), block_size(), 0, s>>>(__VA_ARGS__);   \
        break;                                                               \
      case 8:                                                                \
        kernel<8><<<team_blocks(n, 8), block_size(), 0, s>>>(__VA_ARGS__);   \
        break;                                                               \
      case 16:                                                               \
        kernel<16><<<team_blocks(n, 16), block_size(), 0, s>>>(__VA_ARGS__); \
        break;                                                               \
      default:                                                               \
        kernel<32><<<team_blocks(n, 32), block_size(), 0, s>>>(__VA_ARGS__); \
        break;                                                               \
    }                                                                        \
    FQ_CUDA_CHECK_LAUNCH(#kernel);                                           \
  } while (0)

}  // namespace

void team_neighbourhood_quadrics(DeviceFrame& f, float sigma_b, int team, bool fast_exp, cudaStream_t s) {
  const GridView g = f.grid.view(f.points.data());
  FQ_TEAM_LAUNCH(team_neighbourhood, team, f.n, s, g, f.base_p.data(),
                 Weight{Gaussian::with_sigma(sigma_b), fast_exp}, 2.f * sigma_b, f.nbhd_p.reserve(f.n));
}

void team_diffuse_quadrics(DeviceFrame& f, const FilterParams& p, int team, bool fast_exp, cudaStream_t s) {
  const GridView g = f.grid.view(f.points.data());
  FQ_TEAM_LAUNCH(team_diffusion, team, f.n, s, g, f.nbhd_p.data(),
                 Weight{Gaussian::with_sigma(p.sigma_s), fast_exp},
                 Weight{Gaussian::with_sigma(p.sigma_r), fast_exp}, 2.f * p.sigma_s, f.bl.reserve(f.n),
                 f.bl_p.reserve(f.n));
}

void team_cluster_scores(DeviceFrame& f, const ClusterParams& p, int team, bool fast_exp, cudaStream_t s) {
  const GridView g = f.grid.view(f.points.data());
  FQ_TEAM_LAUNCH(team_score, team, f.n, s, g, f.bl.data(), Weight{Gaussian::with_sigma(p.sigma_d), fast_exp},
                 Weight{Gaussian::with_sigma(p.sigma_q), fast_exp}, 2.f * p.sigma_d,
                 p.method == ClusterMethod::kEuclidean, f.score.reserve(f.n));
}

void team_cluster_links(DeviceFrame& f, const ClusterParams& p, int team, bool fast_exp, cudaStream_t s) {
  const GridView g = f.grid.view(f.points.data());
  FQ_TEAM_LAUNCH(team_link, team, f.n, s, g, f.bl_p.data(), f.score.data(),
                 Weight{Gaussian::with_sigma(p.sigma_d), fast_exp},
                 Weight{Gaussian::with_sigma(p.sigma_q), fast_exp}, 2.f * p.sigma_d,
                 p.method == ClusterMethod::kEuclidean, 1.0f - p.theta, f.next.reserve(f.n));
}

}  // namespace fq::cuda
