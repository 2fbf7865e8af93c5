// CPU parallel loop over independent items. Every item writes only its own outputs, so
// results do not depend on the thread count or on scheduling.
#pragma once

#include <cstdint>

#if defined(FQ_HAVE_OPENMP)
#include <omp.h>
#endif

namespace fq {

template <class F>
void parallel_for(uint32_t n, int threads, F&& f) {
#if defined(FQ_HAVE_OPENMP)
#pragma omp parallel for schedule(dynamic, 256) num_threads(threads)
  for (int64_t i = 0; i < int64_t(n); ++i) f(static_cast<uint32_t>(i));
#else
  (void)threads;
  for (uint32_t i = 0; i < n; ++i) f(i);
#endif
}

/// Hardware threads available to the process.
int hardware_threads();

}  // namespace fq
