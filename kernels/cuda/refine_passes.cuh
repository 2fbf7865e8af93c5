// The "qf+" refinement on the device (kernels/refine_math.h; the CPU engine's
// cpu::refine_positions). Needs the vertex -> triangle table of base_quadrics.
#pragma once

#include <cuda_runtime.h>

#include "kernels/cuda/device_frame.cuh"
#include "core/params.h"
#include "kernels/refine_math.h"

namespace fq::cuda {

/// Scratch of the refinement, kept between frames (grow-only).
struct RefineBuffers {
  DeviceBuffer<Vec3> x;  ///< the other position buffer of the ping-pong with f.moved
  DeviceBuffer<uint8_t> closed;  ///< closed_fan per vertex
  DeviceBuffer<TriangleGeom> geom;
  DeviceBuffer<Vec3> normals[2];
  DeviceBuffer<FreeDirections> dirs;  ///< free_directions per vertex, per round
  DeviceBuffer<float> change;  ///< block sums, then the guard's strength and the rough-input weight
  DeviceBuffer<Vec3> fine;     ///< the fine run's result while the rough-input run goes
  PinnedBuffer<float> h_rough;  ///< the rough-input weight, read back
};

/// Refines f.moved in place (sorted order), one launch per pass as the CPU's passes.
void refine_positions(DeviceFrame& f, RefineBuffers& b, const RefineParams& r, cudaStream_t s);

}  // namespace fq::cuda
