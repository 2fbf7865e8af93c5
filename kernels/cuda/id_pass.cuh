// Track A's step (kernels/temporal_ids.h) on the device: the per-vertex math of
// average_with_ids, one thread a vertex (the ring means of several quantities: one a quantity),
// through the same ring table in blocks and the same
// per-vertex rules (kernels/temporal_math.h), so that the averaged input is the host's bit for
// bit (the file is built without fused multiply-adds, as the host's code has none). The host
// keeps what is per connectivity (begin_id_step builds the tables once) and the decision on
// the typical level (finish_id_step); the device finds that level's median by a radix select on
// its bits, as median_level does. A level that is not a finite non-negative number (an input
// with NaN or infinite coordinates, which the run then rejects) refuses the ids on the device,
// where the host's nth_element would pick some median.
//
// The motion's rigid correction (kernels/rigid_motion.h) runs beside its ring means: three
// more lanes of four through the same passes, and the fit per vertex where each estimate ends.
//
// On the host, the step was some 1.2–2.2 ms of a 2.3–3.2 ms frame on crane (10K vertices, an
// H200 host): sixteen passes over the vertices that a device runs in a few µs each. Its
// kernels and copies are recorded once as a CUDA graph and replayed (launch_graph.cuh): the
// frame's values (unit, origin, blend, the select's start) go up in one small block first.
// Crane's temporal_ids pass on an H200 host, three runs beside the build before: 0.39-0.42 ->
// 0.33-0.36 ms a frame (the run medians).
//
// The stream's state stays on the host (IdTrack), so that the next frame may go to any engine;
// beside it the pass keeps device copies of the last few connectivities' tables (by their
// fingerprint) and of the last few averaged inputs it wrote (by IdTrack::stamp): streams whose
// frames take turns on one engine (fqd) each find theirs.
#pragma once

#include <cuda_runtime.h>

#include <array>
#include <cstdint>
#include <vector>

#include "kernels/cuda/device_buffer.cuh"
#include "kernels/cuda/launch_graph.cuh"
#include "kernels/temporal.h"

namespace fq::cuda {

/// One connectivity's tables on the device.
struct DeviceIdTopology {
  uint64_t fingerprint = 0;  ///< IdTopology::fingerprint; 0: nothing valid
  uint32_t n = 0, m = 0;
  uint64_t used = 0;  ///< the pass's step count when last read
  DeviceBuffer<uint32_t> rows, slots;
  DeviceBuffer<float> inv_count, white;
};

/// One stream's last averaged input on the device.
struct DeviceIdAverage {
  uint64_t stamp = 0;  ///< IdTrack::stamp of what it holds; 0: nothing valid
  uint32_t n = 0;
  uint64_t used = 0;
  DeviceBuffer<float> positions;  ///< 3 floats a vertex, input units
};

class IdPass {
 public:
  static constexpr int kCopies = 4;

  /// average_with_ids with its per-vertex math on the device, on stream `s` (synchronized before
  /// it returns). `scratch` and `threads` serve the host's part (begin_id_step).
  IdStep step(const MeshView& mesh, uint64_t fingerprint, double mean_edge, float strength, IdTrack& track,
              std::vector<float>& averaged, TemporalScratch& scratch, int threads, cudaStream_t s);

  /// The step's chains of launches recorded so far (a frame that replays one records none).
  uint64_t chains_recorded() const { return chains_.recorded(); }

 private:
  DeviceIdTopology& topology_of(const IdTopology& topo, cudaStream_t s);
  DeviceIdAverage& average_of(const IdTrack& track, cudaStream_t s);

  /// What the step's chain of launches is recorded with (launch_graph.cuh): the vertex count and
  /// every buffer it reads or writes, the frame's tables and averaged input among them.
  struct IdChainKey {
    uint32_t n = 0;
    std::array<const void*, 27> buffers{};
    bool operator==(const IdChainKey& o) const { return n == o.n && buffers == o.buffers; }
  };

  DeviceIdTopology topologies_[kCopies];
  DeviceIdAverage averages_[kCopies];
  uint64_t steps_ = 0;
  DeviceBuffer<float> x_;  ///< the raw frame
  DeviceBuffer<Vec3> offset_, motion_[2], wide_;
  DeviceBuffer<Point4> packed_[2];
  DeviceBuffer<Vec3> position_, correction_;  ///< the rigid fit's (kernels/rigid_motion.h)
  DeviceBuffer<Point4> rigid_[6];             ///< RigidInputs' three lanes, then their ring means
  DeviceBuffer<float> level_, partials_;
  DeviceBuffer<uint32_t> histogram_, frame_;  ///< frame_: the frame's values the chain reads
  PinnedBuffer<unsigned char> h_upload_;
  PinnedBuffer<float> h_averaged_, h_partials_;
  PinnedBuffer<uint32_t> h_select_, h_frame_;
  ChainCache<IdChainKey, kCopies> chains_;  ///< declared last: destroyed before the buffers it names
};

}  // namespace fq::cuda
