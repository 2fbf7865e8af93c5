// Device memory in use on the GPUs fqd runs engines on, for /metrics. Device-wide (total -
// free as the driver reports it), so other processes on the GPU count too.
#pragma once

#include <cstdint>
#include <vector>

namespace fq::daemon {

struct GpuMemory {
  int device = 0;
  uint64_t used_bytes = 0, total_bytes = 0;
};

/// One entry per listed device that answers; empty in a build without CUDA.
std::vector<GpuMemory> gpu_memory(const std::vector<int>& devices);

}  // namespace fq::daemon
