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

#include "common/non_copyable.h"
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

/// Device memory (cudaMalloc), counted.
struct DeviceMemory {
  static constexpr const char* kFree = "cudaFree";
  static cudaError_t allocate(void** p, size_t bytes) { return cudaMalloc(p, bytes); }
  static cudaError_t release(void* p) { return cudaFree(p); }
  static void allocated(size_t bytes) { note_device_allocation(bytes); }
  static void freed(size_t bytes) { note_device_free(bytes); }
};

/// Page-locked host memory (cudaMallocHost) for asynchronous transfers.
struct PinnedMemory {
  static constexpr const char* kFree = "cudaFreeHost";
  static cudaError_t allocate(void** p, size_t bytes) { return cudaMallocHost(p, bytes); }
  static cudaError_t release(void* p) { return cudaFreeHost(p); }
  static void allocated(size_t) {}
  static void freed(size_t) {}
};

/// n elements of T in `Memory`: move-only, grow-only.
template <class T, class Memory>
class OwnedBuffer : NonCopyable {
 public:
  OwnedBuffer() = default;
  OwnedBuffer(OwnedBuffer&& o) noexcept { swap(o); }
  OwnedBuffer& operator=(OwnedBuffer&& o) noexcept {
    OwnedBuffer tmp(std::move(o));
    swap(tmp);
    return *this;
  }
  ~OwnedBuffer() {
    if (data_) {
      if (const cudaError_t e = Memory::release(data_); e != cudaSuccess) log_free_failure(Memory::kFree, e);
      Memory::freed(capacity_ * sizeof(T));
    }
  }

  /// Makes room for n elements; contents are not kept when it grows (callers rewrite them).
  T* reserve(size_t n) {
    if (n <= capacity_) return data_;
    if (data_) {
      Memory::freed(capacity_ * sizeof(T));
      FQ_CUDA_CHECK(Memory::release(data_));
    }
    data_ = nullptr;
    capacity_ = 0;
    FQ_CUDA_CHECK(Memory::allocate(reinterpret_cast<void**>(&data_), n * sizeof(T)));
    Memory::allocated(n * sizeof(T));
    capacity_ = n;
    return data_;
  }
  T* data() const { return data_; }
  size_t capacity() const { return capacity_; }

 private:
  void swap(OwnedBuffer& o) noexcept {
    std::swap(data_, o.data_);
    std::swap(capacity_, o.capacity_);
  }
  T* data_ = nullptr;
  size_t capacity_ = 0;
};

template <class T>
using DeviceBuffer = OwnedBuffer<T, DeviceMemory>;
template <class T>
using PinnedBuffer = OwnedBuffer<T, PinnedMemory>;

}  // namespace fq::cuda
