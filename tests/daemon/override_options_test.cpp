// fqpub's and fqstreambench's parameter-override options: what a command line puts on the wire.
#include "clients/common/override_options.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace fq::client {
namespace {

// Parses `args` (after the program name) with the override options only.
Status parse(std::vector<std::string> args, wire::ParamOverrides& out, wire::Compute& compute) {
  CLI::App app;
  OverrideArgs a;
  add_override_options(app, a);
  std::vector<char*> argv{const_cast<char*>("test")};
  for (std::string& s : args) argv.push_back(s.data());
  app.parse(static_cast<int>(argv.size()), argv.data());
  return to_wire(a, out, compute);
}

TEST(OverrideOptions, OnlyTheGivenOptionsAreSet) {
  wire::ParamOverrides o;
  wire::Compute compute{};
  ASSERT_TRUE(parse({"--sigma-r", "0.25", "--constrained", "true", "--sticky-rings", "3", "--mode", "bf",
                     "--cluster-geometry", "filtered", "--compute", "cluster"},
                    o, compute)
                  .ok());
  EXPECT_TRUE(o.has_sigma_r());
  EXPECT_FLOAT_EQ(o.sigma_r(), 0.25f);
  EXPECT_TRUE(o.constrained());
  EXPECT_EQ(o.sticky_rings(), 3u);
  EXPECT_EQ(o.mode(), wire::BF);
  EXPECT_EQ(o.cluster_geometry(), wire::GEOMETRY_FILTERED);
  EXPECT_EQ(compute, wire::CLUSTER);
  EXPECT_FALSE(o.has_sigma_s());
  EXPECT_FALSE(o.has_track_ids());
  EXPECT_FALSE(o.has_cluster_method());

  ASSERT_TRUE(parse({}, o, compute).ok());
  EXPECT_EQ(o.ByteSizeLong(), 0u);  // nothing given: nothing overridden
  EXPECT_EQ(compute, wire::COMPUTE_DEFAULT);
}

TEST(OverrideOptions, UnknownNamesAreRefusedNamingTheOption) {
  wire::ParamOverrides o;
  wire::Compute compute{};
  for (const char* option : {"--mode", "--cluster-method", "--cluster-geometry", "--compute"}) {
    const Status s = parse({option, "nonsense"}, o, compute);
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument) << option;
    EXPECT_NE(s.message().find(option), std::string::npos) << s.message();
  }
}

}  // namespace
}  // namespace fq::client
