#include "daemon/gpu_memory.h"

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
