// Order statistics of measured samples (latencies, pass timings), one definition for the
// daemon's stage metrics, the stream clients and the benchmarks.
#pragma once

#include <vector>

namespace fq {

/// Nearest-rank percentile, q in [0, 1]: the smallest sample with at least a fraction q of
/// the samples at or below it (always one of the samples, never an interpolation); 0 for none.
double percentile(std::vector<double> values, double q);

/// percentile(values, 0.5): for an even count the lower of the two middle samples.
double median(std::vector<double> values);

}  // namespace fq
