// One persistent pool of host threads for every CPU-parallel loop of fq (the frame codec's
// chunks, the CPU engine and frame preparation through fq::parallel_for).
//
// Why not std::thread per call: a frame is encoded in ~1-50 ms, and creating and joining
// threads per call, per frame, on every decode and encode worker of fqd both costs time and
// oversubscribes the cores (8 decode workers x 8 chunk threads on a 16-core host). Here the
// caller always works on its own loop and at most `max_workers - 1` pool threads help it, so
// nested and concurrent calls never wait for each other and never run more threads than the
// pool holds plus the callers themselves.
//
// Why not oneTBB or OpenMP: the codec needs a stable worker slot in [0, max_workers) for
// per-worker scratch space, and idle pool threads must sleep at once (no spin-wait), because
// fqd's codec threads share the cores with the engine and with each other. OpenMP's runtime
// spins by default (OMP_WAIT_POLICY) and nested OpenMP regions from many caller threads each
// start their own team; oneTBB's workers also spin before sleeping.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <mutex>
#include <thread>
#include <type_traits>
#include <vector>

#include "common/non_copyable.h"

namespace fq {

class ThreadPool : NonCopyable {
 public:
  /// A pool of `workers` threads (0: every loop runs on its caller).
  explicit ThreadPool(int workers);
  ~ThreadPool();

  /// The process-wide pool: hardware threads - 1 workers (the caller is the last core).
  /// Started on first use; its threads end with the process.
  static ThreadPool& shared();

  /// Threads of the pool (not counting callers).
  int workers() const { return static_cast<int>(threads_.size()); }

  /// Calls fn(begin, end, worker) over [0, count) cut in ranges of `grain` items, on the
  /// calling thread (worker 0) and at most max_workers - 1 pool threads (workers 1, 2, ...):
  /// worker < max_workers, and no two calls of one run() share a worker id at the same time.
  /// Returns when every range is done. Which worker runs which range is not fixed, so fn
  /// must write only the outputs of its items (and its worker's scratch). fn must not throw
  /// (on a pool thread that ends the process, as in an OpenMP loop; on the caller, the other
  /// ranges are dropped and the exception is rethrown once no worker is inside the loop).
  template <class F>
  void run(size_t count, int max_workers, F&& fn, size_t grain = 1) {
    using Fn = std::remove_reference_t<F>;
    run_ranges(
        count, max_workers, grain,
        [](void* ctx, size_t b, size_t e, size_t w) { (*static_cast<Fn*>(ctx))(b, e, w); },
        const_cast<void*>(static_cast<const void*>(&fn)));
  }

 private:
  using RangeFn = void (*)(void* ctx, size_t begin, size_t end, size_t worker);
  struct Job;

  void run_ranges(size_t count, int max_workers, size_t grain, RangeFn fn, void* ctx);
  void worker_loop();

  std::mutex mutex_;
  std::condition_variable work_;  ///< a job was queued, or the pool stops
  std::condition_variable done_;  ///< a worker left a job
  std::deque<Job*> jobs_;         ///< jobs that may still take a worker, oldest first
  bool stop_ = false;
  std::vector<std::thread> threads_;
};

}  // namespace fq
