// CPU time of a piece of work, wherever it runs: on the thread that does it and on the shared
// pool's threads that help it (thread_pool.h charges their share to the caller's account).
//
// Why thread CPU clocks and not wall time: a stage's wall time on a loaded host includes the
// time its threads waited for a core; what a host is sized by is the CPU each frame costs.
// Why not the process clock: fqstreambench and the tests run fqd inside another program, and
// fqd's threads work on several frames at once.
#pragma once

#include <atomic>
#include <cstdint>

#include "common/non_copyable.h"

namespace fq {

/// CPU nanoseconds the calling thread has run (CLOCK_THREAD_CPUTIME_ID).
int64_t thread_cpu_ns();

/// Where CPU time is summed: one per measured quantity (a stage), shared by every thread that
/// works for it.
using CpuAccount = std::atomic<int64_t>;

/// While a CpuScope lives, the calling thread's CPU time is added to `account`, and so is the
/// time of pool threads running loops this thread starts (ThreadPool::run). Scopes nest: an
/// inner scope's time goes to its account only, the outer one's clock stops meanwhile.
class CpuScope : NonCopyable {
 public:
  explicit CpuScope(CpuAccount& account);
  ~CpuScope();

  /// The account that the calling thread's work is charged to now (null outside any scope).
  static CpuAccount* current();

 private:
  CpuAccount& account_;
  CpuScope* outer_;
  int64_t start_ns_;
};

}  // namespace fq
