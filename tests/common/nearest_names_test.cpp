// "Did you mean": edit distances, and suggestions only for names near enough to be a typo.
#include "common/nearest_names.h"

#include <gtest/gtest.h>

namespace fq {
namespace {

TEST(NearestNames, EditDistanceCountsEachEditOnce) {
  EXPECT_EQ(edit_distance("", ""), 0u);
  EXPECT_EQ(edit_distance("cam0", "cam0"), 0u);
  EXPECT_EQ(edit_distance("cam0", "cam1"), 1u);   // substitution
  EXPECT_EQ(edit_distance("cam", "cam0"), 1u);    // insertion
  EXPECT_EQ(edit_distance("cam00", "cam0"), 1u);  // deletion
  EXPECT_EQ(edit_distance("cma0", "cam0"), 1u);   // swap of neighbours
  EXPECT_EQ(edit_distance("", "abc"), 3u);
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
}

TEST(NearestNames, SuggestsOnlyNamesNearEnough) {
  const std::vector<std::string> streams{"cam0", "north_gate_camera_0042", "preview"};
  EXPECT_EQ(nearest_names("cam1", streams), std::vector<std::string>{"cam0"});
  EXPECT_EQ(nearest_names("north_gate_camera_042", streams),
            std::vector<std::string>{"north_gate_camera_0042"});
  EXPECT_EQ(nearest_names("preveiw", streams), std::vector<std::string>{"preview"});
  EXPECT_TRUE(nearest_names("nosuch", streams).empty());
  EXPECT_TRUE(nearest_names("cam0", streams).empty()) << "a known name needs no suggestion";
  EXPECT_TRUE(nearest_names("x", {"y"}).empty()) << "one letter for one letter is no typo";
  EXPECT_TRUE(nearest_names("anything", {}).empty());
}

TEST(NearestNames, TiesAreAllNamed) {
  EXPECT_EQ(did_you_mean("sigma_z", {"sigma_s", "theta", "sigma_r"}),
            " (did you mean 'sigma_s' or 'sigma_r'?)");
  EXPECT_EQ(did_you_mean("budget_sm", {"budget_ms"}), " (did you mean 'budget_ms'?)");
  EXPECT_EQ(did_you_mean("ab1", {"ab2", "ab3", "ab4", "ab5"}), " (did you mean 'ab2', 'ab3' or 'ab4'?)");
  EXPECT_EQ(did_you_mean("nosuch", {"cam0"}), "");
}

}  // namespace
}  // namespace fq
