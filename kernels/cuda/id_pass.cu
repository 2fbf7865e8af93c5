// Track A's per-vertex math on the device: each kernel is one loop of average_with_ids
// (kernels/temporal_ids.cpp), its ring means summed in the host's order over the same table.
#include <algorithm>
#include <cstring>
#include <cub/block/block_reduce.cuh>
#include <cub/block/block_scan.cuh>
#include <utility>

#include "kernels/cuda/copy_cache.h"
#include "kernels/cuda/cuda_check.cuh"
#include "kernels/cuda/host_staging.h"
#include "kernels/cuda/id_pass.cuh"
#include "kernels/cuda/launch.cuh"
#include "kernels/cuda/launch_graph.cuh"
#include "kernels/rigid_motion.h"
#include "kernels/temporal_ids.h"
#include "kernels/temporal_math.h"
#include "kernels/vertex_ring.h"

namespace fq::cuda {

namespace {

/// Threads per block of the last pass, fixed for its per-block sums.
constexpr unsigned kBlendBlock = 256;
/// The radix select's bins (11, 11 and 10 bits of a level, as median_level takes them).
constexpr uint32_t kBins = 1u << 11;
/// Threads of the block that picks a bin: two bins each.
constexpr unsigned kPickThreads = kBins / 2;
/// The first bin of infinities and NaNs (and, past it, of negative levels).
constexpr uint32_t kNotFinite = 0x7f800000u >> 21;

/// The select's state on the device: the rank sought (within the bins picked so far), the
/// bits picked so far, whether a level was not an ordinary one, and the median found.
struct Select {
  uint32_t rank, bits, broken, median;
};

/// What changes from frame to frame, which the recorded chain reads from device memory: the
/// select's state (from the rank n / 2), the offsets' unit and origin, the blend's rules.
struct IdFrame {
  Select select;
  float unit;
  Vec3 origin;
  IdBlend blend;
};

/// The ring table's pointers on the device (kernels/vertex_ring.h, BlockRing).
struct Ring {
  const uint32_t* rows;
  const uint32_t* slots;
  const float* inv_count;
};

/// block_ring_means' mean at vertex v (< n): v itself, then its block's rows in order (slot
/// v mod kRingBlock of each; a missing one reads the pad, e[n] = -0.0), times 1 / count.
template <class T>
__device__ T ring_mean_at(const Ring& r, const T* e, uint32_t v) {
  const uint32_t b = v / kRingBlock, j = v % kRingBlock;
  T sum = e[v];
  for (uint32_t row = r.rows[b]; row < r.rows[b + 1]; ++row) sum = sum + e[r.slots[kRingBlock * row + j]];
  return r.inv_count[v] * sum;
}

/// RigidInputs' three lanes on the device, each an array of n + 1 Point4 (the pad last).
struct RigidLanes {
  Point4* lane[3];
};

// The displacement from the last averaged input, in mean edges, and the rigid fit's inputs
// (the last averaged positions from `origin`, mean edges); thread 0 sets the pads the ring
// means read.
__global__ void offset_kernel(uint32_t n, const float* x, const float* a, const IdFrame* frame, Vec3* offset,
                              Vec3* m0, Vec3* m1, Vec3* wide, Point4* p0, Point4* p1, Vec3* position,
                              RigidLanes lanes, RigidLanes spare) {
  const uint32_t v = blockIdx.x * blockDim.x + threadIdx.x;
  if (v == 0) {
    const Vec3 z{-0.f, -0.f, -0.f};
    const Point4 z4{-0.f, -0.f, -0.f, -0.f};
    offset[n] = m0[n] = m1[n] = wide[n] = z;
    p0[n] = p1[n] = z4;
    for (int k = 0; k < 3; ++k) lanes.lane[k][n] = spare.lane[k][n] = z4;
  }
  if (v >= n) return;
  const IdPoint at = id_point(x, a, v, frame->unit, frame->origin);
  offset[v] = at.d;
  position[v] = at.p;
  const RigidInputs in = rigid_inputs(at.p, at.d);
  lanes.lane[0][v] = in.p;
  lanes.lane[1][v] = in.q0;
  lanes.lane[2][v] = in.q1;
}

// One ring mean of the displacement's smooth part and of the rigid fit's three lanes, a thread
// for each of the four at each vertex: a thread's gathers wait on memory one after another,
// so four short chains beside each other finish sooner than one long one.
__global__ void ring_kernel(uint32_t n, Ring r, const Vec3* in, Vec3* out, RigidLanes lin, RigidLanes lout) {
  const uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= 4 * n) return;
  const uint32_t which = i / n, v = i - which * n;
  if (which == 0)
    out[v] = ring_mean_at(r, in, v);
  else
    lout.lane[which - 1][v] = ring_mean_at(r, lin.lane[which - 1], v);
}

// One ring mean of the rigid fit's three lanes alone, a thread for each lane at each vertex.
__global__ void lane_kernel(uint32_t n, Ring r, RigidLanes lin, RigidLanes lout) {
  const uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= 3 * n) return;
  const uint32_t which = i / n, v = i - which * n;
  lout.lane[which][v] = ring_mean_at(r, lin.lane[which], v);
}

__device__ inline Vec3 rigid_at(const RigidLanes& l, const Vec3* position, uint32_t v, Vec3 motion) {
  return rigid_correction(RigidInputs{l.lane[0][v], l.lane[1][v], l.lane[2][v]}, motion, position[v]);
}

// smooth_parts' narrow tail: the motion's last ring mean m and its rigid correction c (from the
// lanes' ring means, done), the rest d - (m + c) and its square.
__global__ void narrow_kernel(uint32_t n, Ring r, const Vec3* from, RigidLanes rigid, const Vec3* position,
                              Vec3* offset, Vec3* wide, Vec3* correction, Point4* packed) {
  const uint32_t v = blockIdx.x * blockDim.x + threadIdx.x;
  if (v >= n) return;
  const Vec3 m = ring_mean_at(r, from, v);
  const Vec3 c = rigid_at(rigid, position, v, m);
  const Vec3 rest = offset[v] - (m + c);
  offset[v] = rest;
  wide[v] = m;
  correction[v] = c;
  packed[v] = rest_packed(rest);
}

// smooth_parts' wide tail: the wide estimate (with its rigid correction) less the narrow one.
__global__ void wide_kernel(uint32_t n, Ring r, const Vec3* from, RigidLanes rigid, const Vec3* position,
                            const Vec3* correction, Vec3* wide) {
  const uint32_t v = blockIdx.x * blockDim.x + threadIdx.x;
  if (v >= n) return;
  const Vec3 m = ring_mean_at(r, from, v);
  const Vec3 c = rigid_at(rigid, position, v, m);
  wide[v] = (m + c) - (wide[v] + correction[v]);
}

__global__ void level_inputs_kernel(uint32_t n, Ring r, const Point4* packed, const Vec3* wide, Point4* out) {
  const uint32_t v = blockIdx.x * blockDim.x + threadIdx.x;
  if (v < n) out[v] = level_inputs(ring_mean_at(r, packed, v), wide[v]);
}

__global__ void level_kernel(uint32_t n, Ring r, const Point4* in, float* level, Point4* packed) {
  const uint32_t v = blockIdx.x * blockDim.x + threadIdx.x;
  if (v >= n) return;
  const Point4 m = ring_mean_at(r, in, v);
  level[v] = m.x;
  packed[v] = Point4{m.y, m.z, 0.f, 0.f};
}

/// The bin of a level's bits at `stage` (0, 1, 2), or kBins where it is outside the bins picked.
__device__ inline uint32_t bin_of(uint32_t bits, int stage, const Select& sel) {
  if (stage == 0) return bits >> 21;
  if (stage == 1) return bits >> 21 == sel.bits >> 21 ? (bits >> 10) & 0x7ffu : kBins;
  return bits >> 10 == sel.bits >> 10 ? bits & 0x3ffu : kBins;
}

// The levels counted in their bins of this stage: a block's counts in shared memory, then added.
__global__ void histogram_kernel(uint32_t n, const float* level, int stage, const Select* sel,
                                 uint32_t* bins) {
  __shared__ uint32_t local[kBins];
  for (uint32_t b = threadIdx.x; b < kBins; b += blockDim.x) local[b] = 0;
  __syncthreads();
  const Select s = *sel;
  if (!s.broken) {
    for (uint32_t v = blockIdx.x * blockDim.x + threadIdx.x; v < n; v += gridDim.x * blockDim.x) {
      const uint32_t b = bin_of(__float_as_uint(level[v]), stage, s);
      if (b < kBins) atomicAdd(&local[b], 1u);
    }
  }
  __syncthreads();
  for (uint32_t b = threadIdx.x; b < kBins; b += blockDim.x)
    if (local[b] != 0) atomicAdd(&bins[b], local[b]);
}

// The bin that holds the element `rank` (median_level's bin_of): an exclusive scan of the
// counts, the bin where rank falls, and the rank within it. Clears the counts for the next stage.
__global__ void pick_kernel(int stage, Select* sel, uint32_t* bins) {
  using Scan = cub::BlockScan<uint32_t, kPickThreads>;
  __shared__ typename Scan::TempStorage temp;
  __shared__ uint32_t broken;
  __shared__ Select state;  // read before any thread writes *sel
  const uint32_t t = threadIdx.x;
  const uint32_t bins_here = stage == 2 ? kBins / 2 : kBins;
  uint32_t count[2];
  for (uint32_t k = 0; k < 2; ++k) count[k] = 2 * t + k < bins_here ? bins[2 * t + k] : 0u;
  bins[2 * t] = bins[2 * t + 1] = 0;
  if (t == 0) {
    broken = 0;
    state = *sel;
  }
  __syncthreads();
  for (uint32_t k = 0; k < 2; ++k)
    if (stage == 0 && 2 * t + k >= kNotFinite && count[k] != 0) atomicOr(&broken, 1u);
  uint32_t before[2];
  Scan(temp).ExclusiveSum(count, before);
  __syncthreads();
  Select s = state;
  if (s.broken || broken) {
    if (t == 0) {
      sel->broken = 1;
      sel->median = 0x7f800000u;  // +inf: the ids are refused
    }
    return;
  }
  // The last bin (of those in range) keeps a rank past the counts, as bin_of's loop stops there.
  for (int k = 0; k < 2; ++k) {
    const uint32_t b = 2 * t + k;
    if (b >= bins_here) continue;
    const bool last = b + 1 == bins_here;
    if (s.rank >= before[k] && (s.rank < before[k] + count[k] || last)) {
      const uint32_t shift = stage == 0 ? 21 : (stage == 1 ? 10 : 0);
      s.bits |= b << shift;
      s.rank -= before[k];
      if (stage == 2) s.median = s.bits;
      *sel = s;
    }
  }
}

// The last loop of average_with_ids: the weights, the averaged input (into a, the track's
// copy, and out), and the per-block sums of the weights; nothing where the ids are refused.
__global__ void blend_kernel(uint32_t n, Ring r, const Point4* packed, const float* level, const float* white,
                             const Vec3* offset, const Vec3* wide, const IdFrame* frame, const float* x,
                             float* a, float* partials) {
  using Reduce = cub::BlockReduce<float, kBlendBlock>;
  __shared__ typename Reduce::TempStorage temp;
  const uint32_t v = blockIdx.x * blockDim.x + threadIdx.x;
  IdBlend b = frame->blend;
  b.typical = __uint_as_float(frame->select.median);
  IdWeights w{0.f, 0.f};
  if (v < n && ids_follow(b.typical)) {
    w = b.weights(ring_mean_at(r, packed, v), level[v], white[v]);
    const Vec3 back = b.back(w, offset[v], wide[v]);
    const size_t i = 3 * size_t(v);
    a[i] = x[i] - back.x;
    a[i + 1] = x[i + 1] - back.y;
    a[i + 2] = x[i + 2] - back.z;
  }
  const float share = Reduce(temp).Sum(w.share);
  __syncthreads();
  const float wide_sum = Reduce(temp).Sum(w.wide);
  if (threadIdx.x == 0) {
    partials[2 * blockIdx.x] = share;
    partials[2 * blockIdx.x + 1] = wide_sum;
  }
}

/// `passes` ring means from `from` through the two buffers, and of the rigid lanes from `lanes`
/// through `spare` beside them; returns the last one written, `lanes` and `spare` swapped as
/// they end.
const Vec3* ring_passes(uint32_t n, const Ring& r, const Vec3* from, Vec3* const buffers[2],
                        RigidLanes& lanes, RigidLanes& spare, int passes, cudaStream_t s) {
  for (int p = 0; p < passes; ++p) {
    Vec3* to = buffers[p % 2];
    FQ_LAUNCH(ring_kernel, 4 * n, s, n, r, from, to, lanes, spare);
    from = to;
    std::swap(lanes, spare);
  }
  return from;
}

}  // namespace

DeviceIdTopology& IdPass::topology_of(const IdTopology& topo, cudaStream_t s) {
  bool held = false;
  DeviceIdTopology& c = copy_holding(
      topologies_,
      [&](const DeviceIdTopology& k) {
        return k.fingerprint != 0 && k.fingerprint == topo.fingerprint && k.n == topo.vertices &&
               k.m == topo.triangles;
      },
      held);
  c.used = ++steps_;
  if (held) return c;
  c.fingerprint = 0;
  const size_t row_bytes = topo.ring_rows.size() * sizeof(uint32_t);
  const size_t slot_bytes = topo.ring_slots.size() * sizeof(uint32_t);
  const size_t inv_bytes = topo.ring_inv_count.size() * sizeof(float);
  const size_t white_bytes = topo.white.size() * sizeof(float);
  unsigned char* staging = h_upload_.reserve(row_bytes + slot_bytes + inv_bytes + white_bytes);
  upload_staged(topo.ring_rows.data(), c.rows.reserve(topo.ring_rows.size()), row_bytes, staging, s);
  staging += row_bytes;
  upload_staged(topo.ring_slots.data(), c.slots.reserve(topo.ring_slots.size() + 1), slot_bytes, staging, s);
  staging += slot_bytes;
  upload_staged(topo.ring_inv_count.data(), c.inv_count.reserve(topo.ring_inv_count.size()), inv_bytes,
                staging, s);
  staging += inv_bytes;
  upload_staged(topo.white.data(), c.white.reserve(topo.white.size()), white_bytes, staging, s);
  // The staging buffer is read by the copies: the frame's own uploads wait for them.
  FQ_CUDA_CHECK(cudaStreamSynchronize(s));
  c.fingerprint = topo.fingerprint;
  c.n = topo.vertices;
  c.m = topo.triangles;
  return c;
}

DeviceIdAverage& IdPass::average_of(const IdTrack& track, cudaStream_t s) {
  bool held = false;
  DeviceIdAverage& c = copy_holding(
      averages_,
      [&](const DeviceIdAverage& k) {
        return k.stamp != 0 && k.stamp == track.stamp && k.n == track.vertices;
      },
      held);
  c.used = ++steps_;
  if (held) return c;
  c.stamp = 0;
  c.n = track.vertices;
  const size_t bytes = 3 * size_t(c.n) * sizeof(float);
  upload_staged(track.averaged.data(), c.positions.reserve(3 * size_t(c.n)), bytes, h_upload_.reserve(bytes),
                s);
  FQ_CUDA_CHECK(cudaStreamSynchronize(s));  // as above: the staging buffer is reused next
  return c;
}

IdStep IdPass::step(const MeshView& mesh, uint64_t fingerprint, double mean_edge, float strength,
                    IdTrack& track, std::vector<float>& averaged, TemporalScratch& scratch, int threads,
                    cudaStream_t s) {
  if (!begin_id_step(mesh, fingerprint, mean_edge, track, scratch, threads)) return IdStep{};
  const uint32_t n = mesh.num_vertices;
  const DeviceIdTopology& topo = topology_of(track.topology, s);
  DeviceIdAverage& avg = average_of(track, s);
  avg.stamp = 0;  // the step writes it: a refused frame leaves no valid copy
  const Ring ring{topo.rows.data(), topo.slots.data(), topo.inv_count.data()};
  const size_t bytes = 3 * size_t(n) * sizeof(float);
  float* x = x_.reserve(3 * size_t(n));
  upload_staged(mesh.positions, x, bytes, h_upload_.reserve(bytes), s);
  Vec3* offset = offset_.reserve(n + 1);
  Vec3* buffers[2] = {motion_[0].reserve(n + 1), motion_[1].reserve(n + 1)};
  Vec3* wide = wide_.reserve(n + 1);
  Point4* packed = packed_[0].reserve(n + 1);
  Point4* spare = packed_[1].reserve(n + 1);
  float* level = level_.reserve(n);
  Vec3* position = position_.reserve(n);
  Vec3* correction = correction_.reserve(n);
  Point4* rigid[6];
  for (int k = 0; k < 6; ++k) rigid[k] = rigid_[k].reserve(n + 1);
  uint32_t* bins = histogram_.reserve(kBins);
  constexpr size_t kFrameWords = (sizeof(IdFrame) + sizeof(uint32_t) - 1) / sizeof(uint32_t);
  IdFrame* frame = reinterpret_cast<IdFrame*>(frame_.reserve(kFrameWords));
  const unsigned blocks = (n + kBlendBlock - 1) / kBlendBlock;
  float* partials = partials_.reserve(2 * size_t(blocks));
  float* h_averaged = h_averaged_.reserve(3 * size_t(n));
  float* h_partials = h_partials_.reserve(2 * size_t(blocks));
  Select* h_sel = reinterpret_cast<Select*>(h_select_.reserve(sizeof(Select) / sizeof(uint32_t)));
  // This frame's values, read by the chain: uploaded before it runs.
  const IdFrame now{
      Select{n / 2, 0u, 0u, 0u}, float(1.0 / mean_edge), id_origin(mesh, threads),
      IdBlend{id_history_weight(track, strength), 0.f, track.topology.wide_white, float(mean_edge)}};
  auto* h_frame = reinterpret_cast<IdFrame*>(h_frame_.reserve(kFrameWords));
  std::memcpy(h_frame, &now, sizeof now);
  FQ_CUDA_CHECK(cudaMemcpyAsync(frame, h_frame, sizeof(IdFrame), cudaMemcpyHostToDevice, s));
  const IdChainKey key{n,
                       {x,
                        avg.positions.data(),
                        ring.rows,
                        ring.slots,
                        ring.inv_count,
                        topo.white.data(),
                        offset,
                        buffers[0],
                        buffers[1],
                        wide,
                        packed,
                        spare,
                        level,
                        position,
                        correction,
                        rigid[0],
                        rigid[1],
                        rigid[2],
                        rigid[3],
                        rigid[4],
                        rigid[5],
                        bins,
                        frame,
                        partials,
                        h_averaged,
                        h_partials,
                        h_sel}};
  chains_.run(key, s, [&] {
    RigidLanes lanes{{rigid[0], rigid[1], rigid[2]}}, lanes_spare{{rigid[3], rigid[4], rigid[5]}};
    FQ_LAUNCH(offset_kernel, n, s, n, x, avg.positions.data(), frame, offset, buffers[0], buffers[1], wide,
              packed, spare, position, lanes, lanes_spare);
    // smooth_parts: the narrow motion and its rest, then the wide estimate's difference, each
    // with its rigid correction; the lanes' ring means run beside the motion's, their last one
    // of each estimate before the kernel that fits the rotation.
    const Vec3* from = ring_passes(n, ring, offset, buffers, lanes, lanes_spare, kIdMotionPasses - 1, s);
    FQ_LAUNCH(lane_kernel, 3 * n, s, n, ring, lanes, lanes_spare);
    std::swap(lanes, lanes_spare);
    FQ_LAUNCH(narrow_kernel, n, s, n, ring, from, lanes, position, offset, wide, correction, packed);
    from = ring_passes(n, ring, wide, buffers, lanes, lanes_spare, kIdWidePasses - 1, s);
    FQ_LAUNCH(lane_kernel, 3 * n, s, n, ring, lanes, lanes_spare);
    std::swap(lanes, lanes_spare);
    FQ_LAUNCH(wide_kernel, n, s, n, ring, from, lanes, position, correction, wide);
    static_assert(kIdAgreementPasses == 2, "the level's and the coherence test's passes, as the host's");
    FQ_LAUNCH(level_inputs_kernel, n, s, n, ring, packed, wide, spare);
    FQ_LAUNCH(level_kernel, n, s, n, ring, spare, level, packed);
    // The typical level: median_level's element n / 2, bin by bin.
    FQ_CUDA_CHECK(cudaMemsetAsync(bins, 0, kBins * sizeof(uint32_t), s));
    const unsigned histogram_blocks = std::min<unsigned>((n + 1023) / 1024, 64);
    for (int stage = 0; stage < 3; ++stage) {
      FQ_LAUNCH(histogram_kernel, launch_shape(histogram_blocks, 256), s, n, level, stage, &frame->select,
                bins);
      FQ_LAUNCH(pick_kernel, launch_shape(1, kPickThreads), s, stage, &frame->select, bins);
    }
    FQ_LAUNCH(blend_kernel, launch_shape(blocks, kBlendBlock), s, n, ring, packed, level, topo.white.data(),
              offset, wide, frame, x, avg.positions.data(), partials);
    FQ_CUDA_CHECK(cudaMemcpyAsync(h_averaged, avg.positions.data(), bytes, cudaMemcpyDeviceToHost, s));
    FQ_CUDA_CHECK(
        cudaMemcpyAsync(h_partials, partials, 2 * blocks * sizeof(float), cudaMemcpyDeviceToHost, s));
    FQ_CUDA_CHECK(cudaMemcpyAsync(h_sel, &frame->select, sizeof(Select), cudaMemcpyDeviceToHost, s));
  });
  FQ_CUDA_CHECK(cudaStreamSynchronize(s));
  Select found;
  std::memcpy(&found, h_sel, sizeof found);
  IdMath math;
  std::memcpy(&math.typical, &found.median, sizeof math.typical);
  for (unsigned b = 0; b < blocks; ++b) {  // in order: the report is reproducible
    math.share_sum += h_partials[2 * b];
    math.wide_sum += h_partials[2 * b + 1];
  }
  const IdStep step = finish_id_step(mesh, fingerprint, math, track);
  if (step.ran) {
    averaged.resize(3 * size_t(n));
    parallel_copy(averaged.data(), h_averaged, bytes);
    parallel_copy(track.averaged.data(), h_averaged, bytes);
    avg.stamp = track.stamp;
  }
  return step;
}

}  // namespace fq::cuda
