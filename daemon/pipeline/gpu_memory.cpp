#include "daemon/pipeline/gpu_memory.h"

#include <algorithm>

#include "kernels/fq_features.h"

#if FQ_WITH_CUDA
#include <cuda_runtime_api.h>
#endif

namespace fq::daemon {

std::vector<GpuMemory> gpu_memory(const std::vector<int>& devices) {
  std::vector<GpuMemory> out;
#if FQ_WITH_CUDA
  int current = 0;
  if (cudaGetDevice(&current) != cudaSuccess) return out;
  for (int d : devices) {
    // A device listed twice (two engines on it) is one device: one series.
    if (std::any_of(out.begin(), out.end(), [d](const GpuMemory& g) { return g.device == d; })) continue;
    size_t free_b = 0, total_b = 0;
    if (cudaSetDevice(d) != cudaSuccess || cudaMemGetInfo(&free_b, &total_b) != cudaSuccess) continue;
    out.push_back({d, total_b - free_b, total_b});
  }
  cudaSetDevice(current);
#else
  (void)devices;
#endif
  return out;
}

}  // namespace fq::daemon
