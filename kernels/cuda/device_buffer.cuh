// Owning device and pinned host buffers: move-only, grow-only capacity (the engine drops a
// whole frame's buffers to shrink them), destructors that log and never throw. Every device
// allocation goes through DeviceBuffer::reserve and is counted, and so are the bytes held,
// so a test can check that a steady stream of frames allocates nothing and that memory
// comes back after a huge frame.
#pragma once

#include <cuda_runtime.h>

#include <cstddef>
#include <cstdio>
#include <utility>

#include "kernels/cuda/cuda_check.cuh"

namespace fq::cuda {

/// Counts cudaMalloc calls made by DeviceBuffer and the bytes they hold (process-wide).
void note_device_allocation(size_t bytes);
/// Notes that a DeviceBuffer gave `bytes` back (cudaFree).
void note_device_free(size_t bytes);

/// Logs a failed free from a destructor (which must not throw).
inline void log_free_failure(const char* what, cudaError_t e) {
  std::fprintf(stderr, "fq cuda: %s failed in a destructor: %s (%s)\n", what, cudaGetErrorName(e),
               cudaGetErrorString(e));
}

template <class T>
class DeviceBuffer {
 public:
  DeviceBuffer() = default;
  DeviceBuffer(const DeviceBuffer&) = delete;
  DeviceBuffer& operator=(const DeviceBuffer&) = delete;
  DeviceBuffer(DeviceBuffer&& o) noexcept { swap(o); }
  DeviceBuffer& operator=(DeviceBuffer&& o) noexcept {
    DeviceBuffer tmp(std::move(o));
    swap(tmp);
    return *this;
  }
  ~DeviceBuffer() {
    if (data_) {
      if (const cudaError_t e = cudaFree(data_); e != cudaSuccess) log_free_failure("cudaFree", e);
      note_device_free(capacity_ * sizeof(T));
    }
  }

  /// Makes room for n elements; contents are not kept when it grows (callers rewrite them).
  T* reserve(size_t n) {
    if (n <= capacity_) return data_;
    if (data_) {
      note_device_free(capacity_ * sizeof(T));
      FQ_CUDA_CHECK(cudaFree(data_));
    }
    data_ = nullptr;
    capacity_ = 0;
    FQ_CUDA_CHECK(cudaMalloc(reinterpret_cast<void**>(&data_), n * sizeof(T)));
    note_device_allocation(n * sizeof(T));
    capacity_ = n;
    return data_;
  }
  T* data() const { return data_; }
  size_t capacity() const { return capacity_; }

 private:
  void swap(DeviceBuffer& o) noexcept {
    std::swap(data_, o.data_);
    std::swap(capacity_, o.capacity_);
  }
  T* data_ = nullptr;
  size_t capacity_ = 0;
};

/// Page-locked host memory for asynchronous transfers (same ownership rules).
template <class T>
class PinnedBuffer {
 public:
  PinnedBuffer() = default;
  PinnedBuffer(const PinnedBuffer&) = delete;
  PinnedBuffer& operator=(const PinnedBuffer&) = delete;
  PinnedBuffer(PinnedBuffer&& o) noexcept { swap(o); }
  PinnedBuffer& operator=(PinnedBuffer&& o) noexcept {
    PinnedBuffer tmp(std::move(o));
    swap(tmp);
    return *this;
  }
  ~PinnedBuffer() {
    if (data_) {
      if (const cudaError_t e = cudaFreeHost(data_); e != cudaSuccess) log_free_failure("cudaFreeHost", e);
    }
  }

  T* reserve(size_t n) {
    if (n <= capacity_) return data_;
    if (data_) FQ_CUDA_CHECK(cudaFreeHost(data_));
    data_ = nullptr;
    capacity_ = 0;
    FQ_CUDA_CHECK(cudaMallocHost(reinterpret_cast<void**>(&data_), n * sizeof(T)));
    capacity_ = n;
    return data_;
  }
  T* data() const { return data_; }

 private:
  void swap(PinnedBuffer& o) noexcept {
    std::swap(data_, o.data_);
    std::swap(capacity_, o.capacity_);
  }
  T* data_ = nullptr;
  size_t capacity_ = 0;
};

}  // namespace fq::cuda
