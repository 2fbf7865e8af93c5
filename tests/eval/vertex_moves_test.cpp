// vertex_moves against moves known by construction.
#include "eval/vertex_moves.h"

#include <gtest/gtest.h>

#include <vector>

namespace fq {
namespace {

TEST(VertexMoves, MeanPercentileAndMaxInTheUnit) {
  // 200 vertices, unit 2: 196 moved by 1 along x (0.5 units), then 2, 2.5, 3 and 4 along y or z
  // (1, 1.25, 1.5, 2): the nearest rank ⌈0.99 · 200⌉ = 198 is 1.25, its neighbours 1 and 1.5.
  std::vector<float> before(600, 0.5f), after = before;
  for (size_t i = 0; i < 196; ++i) after[3 * i] += 1.f;
  after[3 * 196 + 1] += 2.f;
  after[3 * 197 + 2] += 2.5f;
  after[3 * 198 + 1] += 3.f;
  after[3 * 199 + 2] += 4.f;
  const VertexMoves m = vertex_moves(before.data(), after.data(), 200, 2.0);
  EXPECT_NEAR(m.mean, (196 * 0.5 + 1.0 + 1.25 + 1.5 + 2.0) / 200, 1e-12);
  EXPECT_DOUBLE_EQ(m.p99, 1.25);
  EXPECT_DOUBLE_EQ(m.max, 2.0);
}

TEST(VertexMoves, NothingMovedOrNothingToMeasure) {
  const std::vector<float> p = {1.f, 2.f, 3.f};
  const VertexMoves still = vertex_moves(p.data(), p.data(), 1, 1.0);
  EXPECT_EQ(still.mean, 0.0);
  EXPECT_EQ(still.p99, 0.0);
  const VertexMoves none = vertex_moves(nullptr, nullptr, 0, 1.0);
  EXPECT_EQ(none.max, 0.0);
  const VertexMoves no_unit = vertex_moves(p.data(), p.data(), 1, 0.0);
  EXPECT_EQ(no_unit.mean, 0.0);
}

}  // namespace
}  // namespace fq
