// CPU parallel loop over independent items. Every item writes only its own outputs, so
// results do not depend on the thread count or on scheduling.
#pragma once

#include <algorithm>
#include <cstdint>

#include "common/thread_pool.h"
#include "core/cancel_token.h"

namespace fq {

/// f(i) for every i in [0, n) on the calling thread and at most threads - 1 threads of the
/// shared host pool (common/thread_pool.h). `grain` items are handed out at a time: 256 suits
/// per-vertex work; coarse items (whole chunks of a reduction) need 1, or a few hundred of
/// them all land on one thread.
/// Under a CancelScope whose token has expired, the chunks not yet started are skipped (the
/// loop's outputs are then unspecified: the engine checks the token after the loop).
template <class F>
void parallel_for(uint32_t n, int threads, F&& f, int grain = 256) {
  const CancelToken* cancel = current_cancel_token();
  const size_t chunk = static_cast<size_t>(std::max(grain, 1));
  ThreadPool::shared().run(
      n, threads,
      [&f, cancel, chunk](size_t begin, size_t end, size_t) {
        // The pool may hand one thread the whole range: the token is checked every `chunk`.
        for (size_t i = begin; i < end;) {
          if (cancel != nullptr && cancel->expired()) return;
          const size_t stop = cancel != nullptr ? std::min(end, i + chunk) : end;
          for (; i < stop; ++i) f(static_cast<uint32_t>(i));
        }
      },
      chunk);
}

/// Hardware threads available to the process.
int hardware_threads();

/// `threads`, or every hardware thread when it is 0 or less (the convention of every
/// `threads` argument).
inline int threads_or_all(int threads) { return threads > 0 ? threads : hardware_threads(); }

/// Reductions run over fixed chunks of kFixedChunk items whose partial results are combined
/// in chunk order, so every sum is bit-identical for any thread count. Each chunk is one
/// work item of parallel_for (grain kOneChunkAtATime).
inline constexpr uint32_t kFixedChunk = 1u << 15;
inline constexpr int kOneChunkAtATime = 1;
inline uint32_t fixed_chunks(uint64_t n) {
  return static_cast<uint32_t>((n + kFixedChunk - 1) / kFixedChunk);
}

}  // namespace fq
