// How far a filter moved the vertices: what fqfilter's report and fq.filter(return_info=True)
// tell a user about a result, so that "the output looks the same" has a number beside it.
#pragma once

#include <cstdint>

namespace fq {

/// Distances between a vertex's position before and after, in `unit` (a mean edge length).
struct VertexMoves {
  double mean = 0.0;
  double p99 = 0.0;  ///< 99th percentile (the nearest rank)
  double max = 0.0;
};

/// Over `n` vertices (3 floats each); all zero when n is 0 or unit is not positive.
VertexMoves vertex_moves(const float* before, const float* after, uint32_t n, double unit);

}  // namespace fq
