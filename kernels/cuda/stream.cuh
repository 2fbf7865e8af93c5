// RAII for a CUDA stream and for the events that time the passes of a frame.
#pragma once

#include <cuda_runtime.h>

#include <string>
#include <utility>
#include <vector>

#include "common/non_copyable.h"
#include "kernels/cuda/cuda_check.cuh"
#include "kernels/cuda/device_buffer.cuh"

namespace fq::cuda {

class Stream : NonCopyable {
 public:
  Stream() { FQ_CUDA_CHECK(cudaStreamCreateWithFlags(&s_, cudaStreamNonBlocking)); }
  ~Stream() {
    if (const cudaError_t e = cudaStreamDestroy(s_); e != cudaSuccess)
      log_free_failure("cudaStreamDestroy", e);
  }
  cudaStream_t get() const { return s_; }
  void sync() const { FQ_CUDA_CHECK(cudaStreamSynchronize(s_)); }

 private:
  cudaStream_t s_ = nullptr;
};

/// Events without timing, for the host to wait on parts of a frame (chunks of a download).
class SyncEvents : NonCopyable {
 public:
  explicit SyncEvents(int count) : events_(count) {
    for (cudaEvent_t& e : events_) FQ_CUDA_CHECK(cudaEventCreateWithFlags(&e, cudaEventDisableTiming));
  }
  ~SyncEvents() {
    for (cudaEvent_t e : events_) {
      if (const cudaError_t r = cudaEventDestroy(e); r != cudaSuccess)
        log_free_failure("cudaEventDestroy", r);
    }
  }
  const cudaEvent_t* data() const { return events_.data(); }
  int size() const { return static_cast<int>(events_.size()); }

 private:
  std::vector<cudaEvent_t> events_;
};

/// A fixed pool of events recorded between passes; after the frame's synchronization the
/// elapsed time between consecutive marks is each pass's device time.
class PassEvents : NonCopyable {
 public:
  explicit PassEvents(int capacity) : events_(capacity) {
    for (cudaEvent_t& e : events_) FQ_CUDA_CHECK(cudaEventCreate(&e));
  }
  ~PassEvents() {
    for (cudaEvent_t e : events_) {
      if (const cudaError_t r = cudaEventDestroy(e); r != cudaSuccess)
        log_free_failure("cudaEventDestroy", r);
    }
  }

  /// Starts a frame: the first mark.
  void begin(cudaStream_t s) {
    names_.clear();
    FQ_CUDA_CHECK(cudaEventRecord(events_[0], s));
  }
  /// Ends the pass `name` here (the events are reused; `name` must be a literal).
  void mark(const char* name, cudaStream_t s) {
    if (names_.size() + 1 >= events_.size()) return;  // more passes than events: untimed
    names_.push_back(name);
    FQ_CUDA_CHECK(cudaEventRecord(events_[names_.size()], s));
  }
  /// The mark `back` marks before the last one (0: the last; the frame's start when there
  /// are fewer).
  cudaEvent_t recent(size_t back) const { return events_[names_.size() >= back ? names_.size() - back : 0]; }
  /// Elapsed device time per pass; call after the stream has been synchronized.
  template <class Out>
  void collect(Out&& out) const {
    for (size_t k = 0; k < names_.size(); ++k) {
      float ms = 0.f;
      FQ_CUDA_CHECK(cudaEventElapsedTime(&ms, events_[k], events_[k + 1]));
      out(names_[k], double(ms));
    }
  }

 private:
  std::vector<cudaEvent_t> events_;
  std::vector<const char*> names_;
};

}  // namespace fq::cuda
