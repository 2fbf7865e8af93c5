// The link forest before the theta cut, in input order, for cluster_control.h (a target
// cluster count): one thread per vertex, kernels/link_export.h's math.
#pragma once

#include <cuda_runtime.h>

#include "core/params.h"
#include "kernels/cuda/device_frame.cuh"

namespace fq::cuda {

/// f.link_parent / f.link_p (device, input order) from f.next, f.bl and the grid; then
/// copies them into f.h_link_parent / f.h_link_p on `s`.
void export_links(DeviceFrame& f, const ClusterParams& p, cudaStream_t s);

}  // namespace fq::cuda
