// The temporal step (kernels/temporal.h) on the device: the CUDA engine's "qf+" result, still
// normalized and in grid order in f.moved, is pulled towards the stream's last result with the
// per-vertex math the CPU engine's step calls (kernels/temporal_math.h, refine_math.h), before
// it goes to input units and is downloaded. The last result is matched on a grid built on the
// device (kernels/grid_nearest.h says why not the host's NearestVertexIndex).
//
// The caller's TemporalHistory stays the stream's state, on the host and left as the CPU
// engine leaves it (positions, normals, stamp), so that the next frame may go to any engine.
// Beside it the engine keeps device copies of the last few histories it wrote, each with the
// history's stamp: a frame whose history holds that stamp reads the copy, any other uploads
// the host arrays.
#pragma once

#include <cuda_runtime.h>

#include <cstdint>
#include <vector>

#include "kernels/cuda/device_frame.cuh"
#include "kernels/frame_prep.h"
#include "kernels/temporal.h"

namespace fq::cuda {

/// One history on the device.
struct DeviceHistory {
  uint64_t stamp = 0;  ///< TemporalHistory::stamp of what it holds; 0: nothing valid
  uint64_t used = 0;   ///< the engine's frame count when last read or written
  uint32_t n = 0;
  DeviceBuffer<float> positions;  ///< 3 floats a vertex, input units and the history's order
  DeviceBuffer<Vec3> normals;
  DeviceBuffer<Vec3> motion;  ///< TemporalHistory::motion, when `moving`
  bool moving = false;
};

class TemporalPass {
 public:
  /// Device copies kept: streams whose frames take turns on one engine (fqd) each find theirs.
  static constexpr int kCopies = 4;

  /// Enqueues the step on f.moved (f's grid, fan and normalization `norm` are the frame's),
  /// with `strength` and the frame's `noise` estimate, and then the result's vertex normals.
  void follow(DeviceFrame& f, const Normalization& norm, const TemporalHistory& history, float strength,
              float noise, cudaStream_t s);
  /// Enqueues what the history takes from the result, once f.out_coords holds it in input
  /// units: the device copy, and the normals and the step's counts for the host.
  void keep(const DeviceFrame& f, cudaStream_t s);
  /// After the stream has passed keep(): `history` becomes the frame's result (`positions`,
  /// downloaded; `mean_edge` its frame's) and the step's report is returned.
  TemporalStep finish(const std::vector<float>& positions, double mean_edge, TemporalHistory& history);

 private:
  /// The copy that holds `history`, uploading it into the least recently used one if none does.
  DeviceHistory& copy_of(const TemporalHistory& history, cudaStream_t s);

  DeviceHistory copies_[kCopies];
  DeviceHistory next_;  ///< buffers the frame's result goes to, then swapped into target_
  DeviceHistory* target_ = nullptr;
  uint64_t frames_ = 0;
  uint32_t n_ = 0;      ///< the frame's vertices
  bool prior_ = false;  ///< the frame had a history to follow
  PinnedBuffer<unsigned char> h_upload_;
  DeviceGrid grid_;  ///< over the history's points, in the frame's normalized units
  DeviceBuffer<Point4> prior_in_, prior_sorted_;
  DeviceBuffer<Vec3> motion_[2];
  DeviceBuffer<MotionLanes> lanes_[2];   ///< each round's offsets and rigid fit inputs
  DeviceBuffer<uint32_t> ring_corners_;  ///< the frame's ring table (kernels/vertex_ring.h)
  DeviceBuffer<uint32_t> match_;
  DeviceBuffer<float> detail_, level_[2];
  DeviceBuffer<uint32_t> covered_;      ///< vertices with a prior, 1 value
  DeviceBuffer<float> share_partials_;  ///< the pull's sum per block, summed on the host in order
  PinnedBuffer<Vec3> h_normals_, h_motion_;
  PinnedBuffer<uint32_t> h_covered_;
  PinnedBuffer<float> h_partials_;
  uint32_t partials_ = 0;
};

}  // namespace fq::cuda
