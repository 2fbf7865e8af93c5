// The copy engine, fqd's stand-in for an engine that costs the host nothing: the result is
// the input's positions, labels all 0 with the mean edge when clustering is asked for, bad
// parameters refused like any engine's; "copy" names it on every surface that picks engines.
#include "kernels/copy_engine.h"

#include <gtest/gtest.h>

#include "kernels/frame_prep.h"
#include "tests/support/test_meshes.h"

namespace fq {
namespace {

TEST(CopyEngine, ResultIsTheInput) {
  const Mesh m = test::make_icosphere(2);
  CopyEngine e;
  Params p;
  FrameResult r;
  ASSERT_TRUE(e.process(m.view(), p, r).ok());
  EXPECT_EQ(r.positions, m.positions);
  EXPECT_TRUE(r.labels.empty());
  EXPECT_EQ(r.num_clusters, 0u);
  ASSERT_EQ(r.timings.size(), 1u);
  EXPECT_EQ(r.timings[0].name, "copy");
  EXPECT_EQ(e.name(), "copy");
}

TEST(CopyEngine, ClusteringGivesOneClusterAndTheMeanEdge) {
  const Mesh m = test::make_icosphere(2);
  CopyEngine e;
  Params p;
  p.cluster = true;
  FrameResult r;
  r.labels.assign(3, 9u);  // a reused result's leftovers are replaced
  ASSERT_TRUE(e.process(m.view(), p, r).ok());
  EXPECT_EQ(r.labels, std::vector<uint32_t>(m.num_vertices(), 0u));
  EXPECT_EQ(r.num_clusters, 1u);
  EXPECT_DOUBLE_EQ(r.mean_edge, mean_edge_length(m.view(), 1));
}

TEST(CopyEngine, InvalidParametersAreRefused) {
  const Mesh m = test::make_icosphere(1);
  CopyEngine e;
  Params p;
  p.filter = p.cluster = false;
  FrameResult r;
  EXPECT_EQ(e.process(m.view(), p, r).code(), StatusCode::kInvalidArgument);
}

TEST(CopyEngine, MadeAndNamedAsAnEngineKind) {
  EngineKind k = EngineKind::kAuto;
  ASSERT_TRUE(parse_engine_kind("copy", k));
  EXPECT_EQ(k, EngineKind::kCopy);
  EXPECT_STREQ(engine_kind_name(k), "copy");
  for (const char* name : {"auto", "cpu", "cuda"}) {
    ASSERT_TRUE(parse_engine_kind(name, k));
    EXPECT_STREQ(engine_kind_name(k), name);
  }
  EXPECT_FALSE(parse_engine_kind("gpu", k));
  EngineOptions o;
  o.kind = EngineKind::kCopy;
  StatusOr<std::unique_ptr<Engine>> made = make_engine(o);
  ASSERT_TRUE(made.ok());
  EXPECT_EQ(made.value()->name(), "copy");
}

}  // namespace
}  // namespace fq
