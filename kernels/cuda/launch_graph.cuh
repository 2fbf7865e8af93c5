// A chain of launches that a pass enqueues every frame with the same shapes and buffers,
// recorded once as a CUDA graph and replayed: one call where the chain made one a kernel.
// Track A's step (id_pass.cu) is some twenty short kernels on a frame of 10K vertices, 3-13 µs
// each on an H200 (about 130 µs in all); launched one by one, the host's calls took 175-220 µs
// a frame, and the device waited on them.
//
// A recorded chain holds its kernels' arguments as they were: what changes from frame to frame
// goes through device memory the chain reads (the pass uploads it before the replay), and what
// the arguments were recorded with (counts, buffers) is the chain's key. A few chains are kept
// by key, so that streams taking turns on one pass (fqd) each replay theirs.
#pragma once

#include <cuda_runtime.h>

#include <cstddef>
#include <cstdint>
#include <utility>

#include "kernels/cuda/copy_cache.h"

namespace fq::cuda {

/// Puts `s` in capture mode (this thread's calls only: another engine's thread may allocate
/// meanwhile).
void begin_chain(cudaStream_t s);
/// Ends the capture on `s` and returns the graph recorded.
cudaGraph_t end_chain(cudaStream_t s);
/// Ends a capture that failed, dropping what it recorded and the error it left, so that `s`
/// and the thread can go on with the next frame.
void abandon_chain(cudaStream_t s);
/// Makes `exec` run `graph` (an update of exec's when the two have the same shape, else a new
/// one) and destroys `graph`.
void install_chain(cudaGraphExec_t& exec, cudaGraph_t graph);
/// Enqueues `exec` on `s`.
void replay_chain(cudaGraphExec_t exec, cudaStream_t s);
void destroy_chain(cudaGraphExec_t exec);

/// The last few chains a pass recorded, by Key (a type with ==).
template <class Key, size_t N>
class ChainCache {
 public:
  ChainCache() = default;
  ChainCache(const ChainCache&) = delete;
  ChainCache& operator=(const ChainCache&) = delete;
  /// A move takes the chains (an engine gives its buffers back by assigning a new pass; the
  /// one moved from destroys what this one held).
  ChainCache(ChainCache&& o) noexcept { swap(o); }
  ChainCache& operator=(ChainCache&& o) noexcept {
    swap(o);
    return *this;
  }
  ~ChainCache() {
    for (Chain& c : chains_) destroy_chain(c.exec);
  }

  /// Runs on `s` the chain that `enqueue()` (launches and copies on s) makes for `key`: the
  /// one recorded for key when there is one, else records enqueue's (in place of the least
  /// recently used) and runs that. Throws what enqueue throws, with nothing recorded.
  template <class Enqueue>
  void run(const Key& key, cudaStream_t s, Enqueue&& enqueue) {
    bool held = false;
    Chain& c = copy_holding(
        chains_, [&](const Chain& k) { return k.exec != nullptr && k.valid && k.key == key; }, held);
    c.used = ++runs_;
    if (!held) {
      c.valid = false;
      begin_chain(s);
      try {
        std::forward<Enqueue>(enqueue)();
      } catch (...) {
        abandon_chain(s);
        throw;
      }
      install_chain(c.exec, end_chain(s));
      c.key = key;
      c.valid = true;
      ++recorded_;
    }
    replay_chain(c.exec, s);
  }

  void swap(ChainCache& o) noexcept {
    std::swap(chains_, o.chains_);
    std::swap(runs_, o.runs_);
    std::swap(recorded_, o.recorded_);
  }

  /// Chains recorded so far (a replay is not one).
  uint64_t recorded() const { return recorded_; }

 private:
  struct Chain {
    Key key{};
    bool valid = false;
    uint64_t used = 0;
    cudaGraphExec_t exec = nullptr;
  };
  Chain chains_[N];
  uint64_t runs_ = 0, recorded_ = 0;
};

}  // namespace fq::cuda
