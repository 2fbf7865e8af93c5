// The one checking macro for CUDA calls, and the fault type it throws. Faults are caught
// at the frame boundary (CudaEngine::process) and turned into a kInternal Status.
#pragma once

#include <cuda_runtime.h>

#include <stdexcept>
#include <string>

namespace fq::cuda {

/// A failed CUDA call: the error, the call's text and where it was made.
class CudaError : public std::runtime_error {
 public:
  CudaError(cudaError_t code, const char* call, const char* file, int line)
      : std::runtime_error(describe(code, call, file, line)), code_(code) {}
  cudaError_t code() const { return code_; }

 private:
  static std::string describe(cudaError_t code, const char* call, const char* file, int line) {
    return std::string(cudaGetErrorName(code)) + " (" + cudaGetErrorString(code) + ") in `" + call + "` at " +
           file + ":" + std::to_string(line);
  }
  cudaError_t code_;
};

inline void check(cudaError_t code, const char* call, const char* file, int line) {
  if (code != cudaSuccess) throw CudaError(code, call, file, line);
}

}  // namespace fq::cuda

/// Throws fq::cuda::CudaError naming the call, file, line and error when `call` fails.
#define FQ_CUDA_CHECK(call) ::fq::cuda::check((call), #call, __FILE__, __LINE__)
