// CPU parallel loop over independent items. Every item writes only its own outputs, so
// results do not depend on the thread count or on scheduling.
#pragma once

#include <cstdint>

#if defined(FQ_HAVE_OPENMP)
#include <omp.h>
#endif

namespace fq {

/// `grain` items are handed out at a time: 256 suits per-vertex work; coarse items (whole
/// chunks of a reduction) need 1, or a few hundred of them all land on one thread.
template <class F>
void parallel_for(uint32_t n, int threads, F&& f, int grain = 256) {
#if defined(FQ_HAVE_OPENMP)
#pragma omp parallel for schedule(dynamic, grain) num_threads(threads)
  for (int64_t i = 0; i < int64_t(n); ++i) f(static_cast<uint32_t>(i));
#else
  (void)threads;
  (void)grain;
  for (uint32_t i = 0; i < n; ++i) f(i);
#endif
}

/// Hardware threads available to the process.
int hardware_threads();

}  // namespace fq
