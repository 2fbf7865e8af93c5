// Checks shared by the CPU engine's bit-exactness tests (thread counts, reused buffers,
// cancel tokens): noisy test meshes and a bit-for-bit comparison of two frame results.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>

#include "eval/noise.h"
#include "kernels/engine.h"

namespace fq::test {

/// `m` with Gaussian noise of 0.25 mean edges (seeded, so reproducible).
inline Mesh noisy(Mesh m, uint64_t seed) {
  add_gaussian_noise(m, 0.25, seed);
  return m;
}

/// Positions bit for bit, labels, cluster count and exported links equal.
inline void expect_identical(const FrameResult& a, const FrameResult& b, const std::string& what) {
  ASSERT_EQ(a.positions.size(), b.positions.size()) << what;
  EXPECT_EQ(std::memcmp(a.positions.data(), b.positions.data(), a.positions.size() * sizeof(float)), 0)
      << what << ": positions differ";
  EXPECT_EQ(a.labels, b.labels) << what;
  EXPECT_EQ(a.num_clusters, b.num_clusters) << what;
  EXPECT_EQ(a.link_parent, b.link_parent) << what;
}

}  // namespace fq::test
