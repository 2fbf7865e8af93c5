// The one nearest-rank definition of percentiles and medians.
#include "common/sample_stats.h"

#include <gtest/gtest.h>

#include <vector>

namespace fq {
namespace {

TEST(CommonSampleStats, NearestRankIsAlwaysASample) {
  const std::vector<double> v = {5, 1, 4, 2, 3};  // unsorted on purpose
  EXPECT_DOUBLE_EQ(percentile(v, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(percentile(v, 0.2), 1.0);   // rank ceil(1.0) = 1
  EXPECT_DOUBLE_EQ(percentile(v, 0.21), 2.0);  // rank ceil(1.05) = 2
  EXPECT_DOUBLE_EQ(percentile(v, 0.9), 5.0);
  EXPECT_DOUBLE_EQ(percentile(v, 1.0), 5.0);
}

TEST(CommonSampleStats, MedianOfEvenCountIsTheLowerMiddle) {
  EXPECT_DOUBLE_EQ(median({4, 1, 3, 2}), 2.0);
  EXPECT_DOUBLE_EQ(median({3, 1, 2}), 2.0);
  EXPECT_DOUBLE_EQ(median({7}), 7.0);
  EXPECT_DOUBLE_EQ(median({}), 0.0);
}

TEST(CommonSampleStats, TenthAndNinetiethOfTenSamples) {
  std::vector<double> v;
  for (int i = 10; i >= 1; --i) v.push_back(i);
  EXPECT_DOUBLE_EQ(percentile(v, 0.1), 1.0);
  EXPECT_DOUBLE_EQ(percentile(v, 0.9), 9.0);
  EXPECT_DOUBLE_EQ(median(v), 5.0);
}

}  // namespace
}  // namespace fq
