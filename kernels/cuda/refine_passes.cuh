// "qf+" on the device (kernels/noise_estimate.h, refine_plan.h, refine_math.h; the CPU engine's
// cpu::estimate_noise and cpu::refine_positions). Needs the vertex -> triangle table of
// base_quadrics.
#pragma once

#include <cuda_runtime.h>

#include "core/params.h"
#include "kernels/cuda/device_frame.cuh"
#include "kernels/noise_estimate.h"
#include "kernels/refine_math.h"
#include "kernels/refine_plan.h"

namespace fq::cuda {

/// Scratch of "qf+", kept between frames (grow-only).
struct RefineBuffers {
  DeviceBuffer<NoiseSample> samples;
  PinnedBuffer<NoiseSample> h_samples;
  DeviceBuffer<Vec3> x;          ///< the other position buffer of the ping-pong with f.moved
  DeviceBuffer<uint8_t> closed;  ///< closed_fan per vertex
  DeviceBuffer<TriangleGeom> geom;
  DeviceBuffer<Vec3> normals[2];
  DeviceBuffer<FreeDirections> dirs;   ///< free_directions per vertex, per round
  DeviceBuffer<Vec3> round;            ///< the positions before a fractional last round
  DeviceBuffer<Vec3> tangent;          ///< per vertex: its tangential move
  DeviceBuffer<SlideLevel> energy[2];  ///< squared tangential move and turn, then local means
};

/// The input positions into f.moved (sorted order) and the noise estimate of them: the samples
/// are computed on the device and read back (the stream is synchronized), the estimate made on
/// the host as the CPU engine makes it.
NoiseEstimate estimate_noise(DeviceFrame& f, RefineBuffers& b, cudaStream_t s);

/// f.moved (the input positions that estimate_noise left there) filtered by `plan`, one launch
/// per pass as the CPU's passes.
void refine_positions(DeviceFrame& f, RefineBuffers& b, const RefinePlan& plan, cudaStream_t s);

}  // namespace fq::cuda
