// The noise estimate's samples, a warp per fit. One thread per sample (two 2-ring fits of
// ~20–48 vertices, each built by linear searches in local memory) left 4,096 samples on about
// one warp per multiprocessor, latency-bound: 0.39 ms a frame on an H100 whatever the mesh
// size. Here a block of two warps makes one sample, a warp per vertex, with the lanes
// building the ring a chunk of candidates at a time, projecting a ring vertex each and
// summing one entry of XᵀX each; the math is kernels/noise_estimate.h's.
#include "kernels/cuda/launch.cuh"
#include "kernels/cuda/noise_samples.cuh"

namespace fq::cuda {

namespace {

constexpr int kWarp = 32;
constexpr unsigned kAll = 0xffffffffu;
static_assert(tuning::kNoiseSampleBlock == 2 * kWarp, "a block is the two warps of one sample");

/// A warp's fit in shared memory: the RingFit noise_sample() reads, and the ring in the frame.
struct WarpFit {
  RingFit fit;
  FitPoint q[kMaxRing];
};

/// Appends to ring[0, count) the corners other than v of s's triangles that it does not hold,
/// in walking order, the first kMaxRing kept: detail::add_one_ring, 32 candidates at a time
/// (within a chunk the first of equal candidates is the one appended). Returns the new count
/// (warp-uniform).
__device__ int add_corners(const FanView& m, uint32_t s, uint32_t v, uint32_t* ring, int count, int lane) {
  const uint32_t b = m.vf_offsets[s], total = 3 * (m.vf_offsets[s + 1] - b);
  for (uint32_t base = 0; base < total && count < kMaxRing; base += kWarp) {
    const uint32_t j = base + lane;
    const uint32_t c = j < total ? m.tris[3 * size_t(m.vf_faces[b + j / 3]) + j % 3] : v;
    bool fresh = c != v;
    for (int k = 0; k < count && fresh; ++k) fresh = ring[k] != c;
    const unsigned same = __match_any_sync(kAll, c);
    fresh = fresh && __ffs(same) - 1 == lane;
    const unsigned took = __ballot_sync(kAll, fresh);
    const int at = count + __popc(took & ((1u << lane) - 1u));
    if (fresh && at < kMaxRing) ring[at] = c;
    count = min(kMaxRing, count + __popc(took));
    __syncwarp();
  }
  return count;
}

__device__ double warp_sum(double x) {
  for (int d = kWarp / 2; d > 0; d /= 2) x += __shfl_xor_sync(kAll, x, d);
  return x;
}

/// Entry i of a design row kept in registers (a dynamic index would put it in local memory).
__device__ double row_entry(const FitPoint& q, int i) {
  double row[6];
  fit_row(q, row);
  double r = row[0];
#pragma unroll
  for (int t = 1; t < 6; ++t) r = i == t ? row[t] : r;
  return r;
}

/// fit_ring(m, x, v, w.fit) by the warp; w.fit.ok and w.fit.count are set for every outcome.
__device__ void fit_ring_warp(const FanView& m, const Vec3* x, uint32_t v, WarpFit& w, int lane) {
  RingFit& fit = w.fit;
  if (lane == 0) fit.ok = false;
  int count = add_corners(m, v, v, fit.ring, 0, lane);
  const int first = count;
  for (int k = 0; k < first; ++k) count = add_corners(m, fit.ring[k], v, fit.ring, count, lane);
  if (lane == 0) {
    fit.count = count;
    fit.first = first;
  }
  if (count < kMinRing) return;
  const FitFrame frame = fit_frame(m, x, v, fit.ring, first);  // every lane alike
  if (!frame.ok) return;
  if (lane == 0) fit.normal = frame.n;
  for (int k = lane; k < count; k += kWarp) w.q[k] = fit_point(frame, x[fit.ring[k]]);
  __syncwarp();
  // XᵀX's lower triangle: lane e < 21 sums entry (i, j) over the ring in order, as fit_ring.
  int i = 0, j = lane;
  while (j > i) j -= ++i;
  double sum = 0.0;
  if (lane < 21)
    for (int k = 0; k < count; ++k) sum += row_entry(w.q[k], i) * row_entry(w.q[k], j);
  double a[6][6], y[6] = {1.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  for (int e = 0, r = 0; r < 6; ++r)
    for (int c = 0; c <= r; ++c, ++e) a[r][c] = a[c][r] = __shfl_sync(kAll, sum, e);
  if (!detail::solve6(a, y)) return;  // every lane alike
  double b0 = 0.0;
  for (int k = lane; k < count; k += kWarp) {
    const double ak = intercept_weight(y, w.q[k]);
    fit.weight[k] = float(ak);
    b0 += ak * w.q[k].h;
  }
  b0 = warp_sum(b0);
  if (lane == 0) finish_fit(y[0], b0, fit);
}

/// noise_sample()'s correlation term c by the warp (the same terms, summed in another order).
__device__ double white_covariance_warp(const RingFit& fv, const RingFit& fu, uint32_t v, uint32_t u,
                                        int lane) {
  double c = 0.0;
  for (int k = lane; k < fv.count; k += kWarp) {
    const uint32_t r = fv.ring[k];
    if (r == u) c -= fv.weight[k];
    for (int l = 0; l < fu.count; ++l)
      if (fu.ring[l] == r) c += double(fv.weight[k]) * fu.weight[l];
  }
  for (int l = lane; l < fu.count; l += kWarp)
    if (fu.ring[l] == v) c -= fu.weight[l];
  return warp_sum(c);
}

/// Block k (two warps) makes sample k: warp 0 fits v, warp 1 its partner u.
__global__ void __launch_bounds__(tuning::kNoiseSampleBlock)
    noise_sample_kernel(FanView m, const Vec3* x, uint32_t stride, NoiseSample* out) {
  __shared__ alignas(alignof(WarpFit)) unsigned char raw[2 * sizeof(WarpFit)];
  WarpFit* fits = reinterpret_cast<WarpFit*>(raw);
  const uint32_t v = blockIdx.x * stride;
  const int warp = threadIdx.x / kWarp, lane = threadIdx.x % kWarp;
  if (m.vf_offsets[v + 1] == m.vf_offsets[v]) {  // block-uniform
    if (threadIdx.x == 0) out[blockIdx.x] = no_noise_sample();
    return;
  }
  const uint32_t u = sample_partner(m, v);
  fit_ring_warp(m, x, warp == 0 ? v : u, fits[warp], lane);
  __syncthreads();
  if (warp != 0) return;
  const RingFit &fv = fits[0].fit, &fu = fits[1].fit;
  NoiseSample s = no_noise_sample();
  if (fv.ok) {
    s.z_v = fv.z;
    keep_direction_terms(m, x, v, fv, s);
  }
  if (fv.ok && fu.ok) {  // warp-uniform
    s.z_u = fu.z;
    s.white_correlation = white_correlation(white_covariance_warp(fv, fu, v, u, lane), fv, fu);
  }
  if (lane == 0) out[blockIdx.x] = s;
}

}  // namespace

void noise_samples(const FanView& fan, const Vec3* x, uint32_t stride, uint32_t count, NoiseSample* out,
                   cudaStream_t s) {
  if (count == 0) return;
  FQ_LAUNCH(noise_sample_kernel, launch_shape(count, tuning::kNoiseSampleBlock), s, fan, x, stride, out);
}

}  // namespace fq::cuda
