// The temporal step on the device: a thread per vertex (per lane of a vertex in the ring means
// of the motion's lanes), each calling the math of kernels/temporal_math.h, refine_math.h and
// grid_nearest.h as kernels/temporal.cpp does.
#include <cooperative_groups.h>

#include <cub/block/block_reduce.cuh>
#include <utility>

#include "kernels/cuda/copy_cache.h"
#include "kernels/cuda/cuda_check.cuh"
#include "kernels/cuda/device_grid.cuh"
#include "kernels/cuda/host_staging.h"
#include "kernels/cuda/launch.cuh"
#include "kernels/cuda/temporal_pass.cuh"
#include "kernels/grid_build.h"
#include "kernels/grid_nearest.h"
#include "kernels/refine_math.h"
#include "kernels/temporal_math.h"
#include "kernels/vertex_ring.h"

namespace fq::cuda {

namespace {

/// The first sphere a match looks in, in mean edges: the host index's (half its cell).
constexpr float kFirstRadius = 0.5f;
/// Cells of the history's grid, in mean edges: a match then looks at a few cells.
constexpr float kPriorCell = 1.f;
/// Threads per block of the pull, fixed for its per-block sums.
constexpr unsigned kPullBlock = 256;
/// Threads per block of the step's per-vertex kernels (the lookups, the ring table, the
/// normals). A lookup walks a few grid cells on its thread, so these kernels wait on their loads;
/// crane's 10K vertices in blocks of the engine's 256 filled 40 of an H100's 132
/// multiprocessors, in blocks of 64 they fill all of them.
constexpr unsigned kVertexBlock = 64;

/// The shape of a per-vertex kernel over n vertices (grid_size's bounds and test hook hold).
LaunchShape vertex_shape(uint32_t n) { return launch_shape(grid_size(n, kVertexBlock), kVertexBlock); }

__global__ void prior_points_kernel(uint32_t n, const float* positions, Normalization norm, Point4* out) {
  const uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  const Vec3 p = norm.to_normalized(positions + 3 * size_t(i));
  out[i] = {p.x, p.y, p.z, 0.f};
}

// A round's lanes at a vertex x moved by m: its offset to the prior vertex nearest to x + m
// (none found: no offset).
__device__ MotionLanes round_lanes(const GridView& prior, Vec3 x, Vec3 m) {
  const uint32_t j = nearest_in_grid(prior, x + m, kPriorReach, kFirstRadius);
  return motion_lanes(x, j == kNoNearest ? Vec3{0.f, 0.f, 0.f} : xyz(prior.points[j]) - x);
}

// The first round's lanes, from the predicted motion (none: from rest).
__global__ void offset_kernel(uint32_t n, GridView prior, const Vec3* x, const Vec3* motion,
                              MotionLanes* lanes) {
  const uint32_t v = blockIdx.x * blockDim.x + threadIdx.x;
  if (v >= n) return;
  lanes[v] = round_lanes(prior, x[v], motion != nullptr ? motion[v] : Vec3{0.f, 0.f, 0.f});
}

// A later round's lanes, from the motion fitted to the last round's ring means (`mean`): the
// fit and the next lookup in one kernel, as neither reads another vertex.
__global__ void refit_kernel(uint32_t n, GridView prior, const Vec3* x, const MotionLanes* mean,
                             MotionLanes* lanes) {
  const uint32_t v = blockIdx.x * blockDim.x + threadIdx.x;
  if (v < n) lanes[v] = round_lanes(prior, x[v], fitted_motion(mean[v], x[v]));
}

// Each vertex's predicted motion: that of the prior vertex nearest to x (prior_motion in the
// history's order and input units; unit: 1 / the frame's mean edge).
__global__ void prediction_kernel(uint32_t n, GridView prior, const uint32_t* prior_order,
                                  const Vec3* prior_motion, float unit, const Vec3* x, Vec3* motion) {
  const uint32_t v = blockIdx.x * blockDim.x + threadIdx.x;
  if (v >= n) return;
  const uint32_t j = nearest_in_grid(prior, x[v], kPriorReach, kFirstRadius);
  const bool found = j != kNoNearest;
  motion[v] = predicted_motion(found, found ? prior_motion[prior_order[j]] : Vec3{0.f, 0.f, 0.f}, unit);
}

// The frame's ring table: the step's twenty-odd ring means then read each vertex's neighbours
// directly instead of through its triangles (the same additions in the same order).
__global__ void ring_table_kernel(uint32_t n, FanView fan, uint32_t* corners) {
  const uint32_t v = blockIdx.x * blockDim.x + threadIdx.x;
  if (v < n) ring_slots(fan, v, corners);
}

// The motion fitted to the last round's ring means (`mean`), kept in input order and units
// for the next frame (order: grid -> input; edge: the frame's mean edge); the final match from
// x + motion, its detail o along the prior normal and o²; the vertices with a match are counted
// (one atomic a warp: the count does not depend on their order).
__global__ void detail_kernel(uint32_t n, GridView prior, const uint32_t* prior_order,
                              const Vec3* prior_normals, const Vec3* x, const MotionLanes* mean,
                              const uint32_t* order, float edge, Vec3* kept, uint32_t* match, float* detail,
                              float* level, uint32_t* covered) {
  const uint32_t v = blockIdx.x * blockDim.x + threadIdx.x;
  bool found = false;
  if (v < n) {
    const Vec3 m = fitted_motion(mean[v], x[v]);
    kept[order[v]] = edge * m;
    const uint32_t j = nearest_in_grid(prior, x[v] + m, kPriorReach, kFirstRadius);
    found = j != kNoNearest;
    const float o = found ? prior_detail(x[v], m, xyz(prior.points[j]), prior_normals[prior_order[j]]) : 0.f;
    match[v] = j;
    detail[v] = o;
    level[v] = o * o;
  }
  const unsigned ballot = __ballot_sync(0xffffffffu, found);  // every lane gets here: blocks are whole warps
  if ((threadIdx.x & 31u) == 0 && ballot != 0) atomicAdd(covered, unsigned(__popc(ballot)));
}

// x pulled along the prior normal by share × o, unless the frame is a scene cut; the shares'
// sum per block (a fixed tree: reproducible).
__global__ void pull_kernel(uint32_t n, const uint32_t* prior_order, const Vec3* prior_normals,
                            const uint32_t* match, const float* detail, const float* level, float strength,
                            float noise, const uint32_t* covered, Vec3* x, float* partials) {
  using Reduce = cub::BlockReduce<float, kPullBlock>;
  __shared__ typename Reduce::TempStorage temp;
  const uint32_t v = blockIdx.x * blockDim.x + threadIdx.x;
  float share = 0.f;
  if (v < n && match[v] != kNoNearest && !scene_cut(prior_coverage(*covered, n))) {
    share = prior_share(level[v], strength, noise);
    x[v] = x[v] + (share * detail[v]) * prior_normals[prior_order[match[v]]];
  }
  const float sum = Reduce(temp).Sum(share);
  if (threadIdx.x == 0) partials[blockIdx.x] = sum;
}

// The result's vertex normals, in input order (rank: input -> grid order).
__global__ void normals_kernel(uint32_t n, FanView fan, const Vec3* x, const uint32_t* rank, Vec3* normals) {
  const uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n) normals[i] = vertex_normal(fan, x, rank[i]);
}

/// How a ring mean's input T splits into elements of a thread each: kLanes of E a vertex.
template <class T>
struct RingLanes {
  using E = T;
  static constexpr uint32_t kLanes = 1;
};
// MotionLanes a thread a lane: the same additions in the same order as the whole struct's (its
// sums are per component), with four times the threads; a 64-byte element a thread left
// crane's 10K vertices to a third of the multiprocessors, waiting on its loads.
template <>
struct RingLanes<MotionLanes> {
  using E = Point4;
  static constexpr uint32_t kLanes = 4;
};
static_assert(sizeof(MotionLanes) == 4 * sizeof(Point4), "MotionLanes is four lanes");

// `passes` ring means of a (b the other buffer), in one launch: a pass over a frame of 10K
// vertices takes a few microseconds, about what a launch costs, so each of the step's forty-odd
// passes waited on its own launch; a barrier across the grid between passes costs less.
// Grid-stride, so any n fits the grid a cooperative launch allows.
template <class T>
__global__ void ring_means_kernel(uint32_t n, RingView ring, T* a, T* b, int passes) {
  using E = typename RingLanes<T>::E;
  constexpr uint32_t kLanes = RingLanes<T>::kLanes;
  const cooperative_groups::grid_group grid = cooperative_groups::this_grid();
  const uint64_t items = uint64_t(kLanes) * n;
  for (int p = 0; p < passes; ++p) {
    const E* in = reinterpret_cast<const E*>(p % 2 == 0 ? a : b);
    E* out = reinterpret_cast<E*>(p % 2 == 0 ? b : a);
    for (uint64_t t = grid.thread_rank(); t < items; t += grid.num_threads())
      out[t] = ring_mean_of<E>(ring, Lane<E, kLanes>{in + t % kLanes}, uint32_t(t / kLanes));
    if (p + 1 < passes) grid.sync();
  }
}

/// `passes` ring means of a (b the other buffer); returns the buffer that holds the last.
template <class T>
T* ring_means(const RingView& ring, T* a, T* b, int passes, uint32_t n, cudaStream_t s) {
  if (passes <= 0) return a;
  FQ_LAUNCH_COOPERATIVE(ring_means_kernel<T>, uint64_t(RingLanes<T>::kLanes) * n, s, n, ring, a, b, passes);
  return passes % 2 == 0 ? a : b;
}

}  // namespace

DeviceHistory& TemporalPass::copy_of(const TemporalHistory& history, cudaStream_t s) {
  bool held = false;
  DeviceHistory& c = copy_holding(
      copies_,
      [&](const DeviceHistory& k) { return !history.empty() && k.stamp != 0 && k.stamp == history.stamp; },
      held);
  if (held) return c;
  c.stamp = 0;
  c.n = static_cast<uint32_t>(history.positions.size() / 3);
  c.moving = false;
  if (!history.empty() && c.n > 0) {  // written by another engine, or pushed out of this one's copies
    const size_t bytes = 3 * size_t(c.n) * sizeof(float);
    c.moving = history.motion.size() == history.positions.size();
    unsigned char* staging = h_upload_.reserve((c.moving ? 3 : 2) * bytes);
    upload_staged(history.positions.data(), c.positions.reserve(3 * size_t(c.n)), bytes, staging, s);
    upload_staged(history.normals.data(), c.normals.reserve(c.n), bytes, staging + bytes, s);
    if (c.moving) upload_staged(history.motion.data(), c.motion.reserve(c.n), bytes, staging + 2 * bytes, s);
  }
  return c;
}

void TemporalPass::follow(DeviceFrame& f, const Normalization& norm, const TemporalHistory& history,
                          float strength, float noise, cudaStream_t s) {
  const uint32_t n = f.n;
  n_ = n;
  prior_ = !history.empty();
  target_ = &copy_of(history, s);
  target_->stamp = 0;  // this frame's result replaces it: a frame stopped from here leaves no valid copy
  target_->used = ++frames_;
  const FanView fan{f.tris.data(), f.vf_start.data(), f.vf_faces.data()};
  Vec3* x = f.moved.data();
  uint32_t* covered = covered_.reserve(1);
  FQ_CUDA_CHECK(cudaMemsetAsync(covered, 0, sizeof(uint32_t), s));
  if (prior_) {
    uint32_t* corners = ring_corners_.reserve(6 * size_t(f.m));  // two slots a fan entry, 3 a triangle
    FQ_LAUNCH(ring_table_kernel, vertex_shape(n), s, n, fan, corners);
    const RingView ring{f.vf_start.data(), corners};
    const uint32_t m = target_->n;
    GridView prior{};  // no points: no vertex finds a prior
    if (m > 0) {
      Point4* in = prior_in_.reserve(m);
      FQ_LAUNCH(prior_points_kernel, m, s, m, target_->positions.data(), norm, in);
      // Over the frame's bounds: the history's points outside them go to the open edge cells.
      const GridLayout& frame = f.grid.layout;
      const Vec3 lo = frame.origin;
      const Vec3 hi{lo.x + frame.cell * float(frame.nx), lo.y + frame.cell * float(frame.ny),
                    lo.z + frame.cell * float(frame.nz)};
      build_device_grid(choose_grid_layout(lo, hi, kPriorCell, m), in, m, grid_, prior_sorted_.reserve(m), s);
      prior = grid_.view(prior_sorted_.data());
    }
    Vec3* buffers[2] = {motion_[0].reserve(n), motion_[1].reserve(n)};
    MotionLanes* lanes[2] = {lanes_[0].reserve(n), lanes_[1].reserve(n)};
    const Vec3* motion = nullptr;  // none: the first lookups are from x
    if (target_->moving) {
      FQ_LAUNCH(prediction_kernel, vertex_shape(n), s, n, prior, grid_.order.data(), target_->motion.data(),
                float(1.0 / norm.mean_edge), x, buffers[0]);
      motion = ring_means(ring, buffers[0], buffers[1], kPredictionPasses, n, s);
    }
    // Local ICP: match, fit, match again (each later round's lookup runs from the last fit, and
    // the detail kernel's from the final one).
    static_assert(kMotionIterations >= 1, "the detail kernel fits the last round's means");
    FQ_LAUNCH(offset_kernel, vertex_shape(n), s, n, prior, x, motion, lanes[0]);
    MotionLanes* mean = ring_means(ring, lanes[0], lanes[1], kMotionPasses, n, s);
    for (int it = 1; it < kMotionIterations; ++it) {
      MotionLanes* spare = mean == lanes[0] ? lanes[1] : lanes[0];
      FQ_LAUNCH(refit_kernel, vertex_shape(n), s, n, prior, x, mean, spare);
      mean = ring_means(ring, spare, mean, kMotionPasses, n, s);
    }
    uint32_t* match = match_.reserve(n);
    float* detail = detail_.reserve(n);
    float* level = level_[0].reserve(n);
    FQ_LAUNCH(detail_kernel, vertex_shape(n), s, n, prior, grid_.order.data(), target_->normals.data(), x,
              mean, f.grid.order.data(), float(norm.mean_edge), next_.motion.reserve(n), match, detail, level,
              covered);
    const float* local = ring_means(ring, level, level_[1].reserve(n), kAgreementPasses, n, s);
    partials_ = (n + kPullBlock - 1) / kPullBlock;
    FQ_LAUNCH(pull_kernel, launch_shape(partials_, kPullBlock), s, n, grid_.order.data(),
              target_->normals.data(), match, detail, local, strength, noise, covered, x,
              share_partials_.reserve(partials_));
  }
  FQ_LAUNCH(normals_kernel, vertex_shape(n), s, n, fan, x, f.grid.rank.data(), next_.normals.reserve(n));
}

void TemporalPass::keep(const DeviceFrame& f, cudaStream_t s) {
  const uint32_t n = n_;
  FQ_CUDA_CHECK(cudaMemcpyAsync(next_.positions.reserve(3 * size_t(n)), f.out_coords.data(),
                                3 * size_t(n) * sizeof(float), cudaMemcpyDeviceToDevice, s));
  FQ_CUDA_CHECK(cudaMemcpyAsync(h_normals_.reserve(n), next_.normals.data(), n * sizeof(Vec3),
                                cudaMemcpyDeviceToHost, s));
  FQ_CUDA_CHECK(
      cudaMemcpyAsync(h_covered_.reserve(1), covered_.data(), sizeof(uint32_t), cudaMemcpyDeviceToHost, s));
  if (prior_) {
    FQ_CUDA_CHECK(cudaMemcpyAsync(h_partials_.reserve(partials_), share_partials_.data(),
                                  partials_ * sizeof(float), cudaMemcpyDeviceToHost, s));
    FQ_CUDA_CHECK(cudaMemcpyAsync(h_motion_.reserve(n), next_.motion.data(), n * sizeof(Vec3),
                                  cudaMemcpyDeviceToHost, s));
  }
  // The result's buffers become the copy (the ones it replaces are the next frame's to write).
  std::swap(target_->positions, next_.positions);
  std::swap(target_->normals, next_.normals);
  if (prior_) std::swap(target_->motion, next_.motion);
  target_->moving = false;  // until finish() knows the frame was no scene cut
  target_->n = n;
}

TemporalStep TemporalPass::finish(const std::vector<float>& positions, double mean_edge,
                                  TemporalHistory& history) {
  const uint32_t n = n_;
  TemporalStep step;
  if (prior_) {
    step.coverage = prior_coverage(*h_covered_.data(), n);
    if (scene_cut(step.coverage)) {
      history.clear();
      ++history.resets;
      step.reset = true;
    } else {
      double pulled = 0.0;
      for (uint32_t k = 0; k < partials_; ++k) pulled += h_partials_.data()[k];
      step.share = float(pulled / n);
    }
  }
  const size_t bytes = 3 * size_t(n) * sizeof(float);
  history.positions.resize(3 * size_t(n));
  parallel_copy(history.positions.data(), positions.data(), bytes);
  history.normals.resize(3 * size_t(n));
  parallel_copy(history.normals.data(), h_normals_.data(), bytes);
  history.normals_pending = 0;
  // The motion found, for the next frame's prediction; none after a first frame or a scene cut.
  target_->moving = prior_ && !step.reset;
  if (target_->moving) {
    history.motion.resize(3 * size_t(n));
    parallel_copy(history.motion.data(), h_motion_.data(), bytes);
  } else {
    history.motion.clear();
  }
  history.mean_edge = mean_edge;
  history.stamp = next_history_stamp();
  ++history.frames;
  target_->stamp = history.stamp;
  return step;
}

}  // namespace fq::cuda
