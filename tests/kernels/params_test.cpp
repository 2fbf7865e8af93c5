// Parameter validation (core/params.h): every bad value is an kInvalidArgument whose
// message names the parameter, both from validate() and from the engine, and the engine
// stays usable afterwards.
#include "core/params.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>
#include <string>

#include "core/param_table.h"
#include "kernels/cpu_engine.h"
#include "tests/support/param_values.h"
#include "tests/support/test_meshes.h"

namespace fq {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

Params clustering_params() {
  Params p;
  p.cluster = true;
  return p;
}

void expect_rejected(const Params& p, const std::string& name) {
  const Status s = validate(p);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument) << name;
  EXPECT_NE(s.message().find(name), std::string::npos)
      << "message '" << s.message() << "' does not name " << name;
}

TEST(KernelParams, DefaultsAreValid) {
  EXPECT_TRUE(validate(Params{}).ok());
  EXPECT_TRUE(validate(clustering_params()).ok());
  Params cluster_only = clustering_params();
  cluster_only.filter = false;
  EXPECT_TRUE(validate(cluster_only).ok());
}

TEST(KernelParams, FilterSigmasMustBePositiveAndFinite) {
  for (const char* name : {"sigma_s", "sigma_r"}) {
    for (float bad : {0.f, -1.f, kNaN, -kInf, kInf, 2e4f}) {
      Params p;
      (std::string(name) == "sigma_s" ? p.filtering.sigma_s : p.filtering.sigma_r) = bad;
      SCOPED_TRACE(std::to_string(bad));
      expect_rejected(p, name);
    }
  }
}

TEST(KernelParams, KnownNoiseAndStrengthAreBounded) {
  for (float bad : {-0.1f, kNaN, kInf, 11.f}) {
    Params p;
    p.filtering.refine.known_noise = bad;
    SCOPED_TRACE(std::to_string(bad));
    expect_rejected(p, "known_noise");
    p = Params{};
    p.filtering.refine.strength = bad;
    expect_rejected(p, "strength");
  }
  Params p;
  p.filtering.refine.known_noise = 0.f;  // estimated
  p.filtering.refine.strength = 0.f;     // no filtering: allowed
  EXPECT_TRUE(validate(p).ok());
  p.filtering.refine.known_noise = 10.f;
  p.filtering.refine.strength = 10.f;
  EXPECT_TRUE(validate(p).ok());
}

TEST(KernelParams, OptionalSigmasAcceptZeroAsDefault) {
  for (const char* name : {"sigma_b", "sigma_n"}) {
    Params p;
    float& v = std::string(name) == "sigma_b" ? p.filtering.sigma_b : p.filtering.sigma_n;
    v = 0.f;
    EXPECT_TRUE(validate(p).ok()) << name;
    v = 0.7f;
    EXPECT_TRUE(validate(p).ok()) << name;
    for (float bad : {-0.5f, kNaN, kInf}) {
      v = bad;
      expect_rejected(p, name);
    }
  }
  EXPECT_FLOAT_EQ(Params{}.filtering.effective_sigma_b(), 0.75f);  // sigma_s / 2 (default sigma_s 1.5)
  EXPECT_FLOAT_EQ(Params{}.filtering.effective_sigma_n(), 0.75f);
}

TEST(KernelParams, TikhonovRange) {
  Params p;
  p.filtering.tikhonov = 0.f;  // the paper's solver
  EXPECT_TRUE(validate(p).ok());
  for (float bad : {-0.01f, kNaN, 1e4f}) {
    p.filtering.tikhonov = bad;
    expect_rejected(p, "tikhonov");
  }
}

TEST(KernelParams, ClusterSigmas) {
  for (const char* name : {"sigma_d", "sigma_q"}) {
    for (float bad : {0.f, -3.f, kNaN}) {
      Params p = clustering_params();
      (std::string(name) == "sigma_d" ? p.clustering.sigma_d : p.clustering.sigma_q) = bad;
      expect_rejected(p, name);
    }
  }
}

TEST(KernelParams, ThetaInHalfOpenUnitInterval) {
  Params p = clustering_params();
  for (float good : {1e-6f, 0.5f, 1.f}) {
    p.clustering.theta = good;
    EXPECT_TRUE(validate(p).ok()) << good;
  }
  for (float bad : {0.f, -0.1f, 1.0001f, 2.f, kNaN}) {
    p.clustering.theta = bad;
    SCOPED_TRACE(std::to_string(bad));
    expect_rejected(p, "theta");
  }
}

TEST(KernelParams, NothingToCompute) {
  Params p;
  p.filter = false;
  EXPECT_EQ(validate(p).code(), StatusCode::kInvalidArgument);
}

TEST(KernelParams, EngineRejectsBadParamsAndKeepsWorking) {
  const Mesh mesh = test::make_icosphere(1);
  CpuEngine engine(2);
  FrameResult out;
  Params bad = clustering_params();
  bad.clustering.theta = 0.f;
  const Status s = engine.process(mesh.view(), bad, out);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("theta"), std::string::npos) << s.message();
  EXPECT_TRUE(out.labels.empty());
  EXPECT_EQ(out.num_clusters, 0u);
  bad = Params{};
  bad.filtering.sigma_r = kNaN;
  EXPECT_NE(engine.process(mesh.view(), bad, out).message().find("sigma_r"), std::string::npos);
  ASSERT_TRUE(engine.process(mesh.view(), clustering_params(), out).ok());
  EXPECT_EQ(out.positions.size(), mesh.positions.size());
  EXPECT_EQ(out.labels.size(), mesh.num_vertices());
}

TEST(KernelParams, MethodNamesRoundTrip) {
  const ParamRow& mode = *find_param("mode");
  const ParamRow& cluster_method = *find_param("cluster_method");
  EXPECT_EQ(choice_names(mode), "qf+ or qf or bf");
  EXPECT_EQ(choice_names(cluster_method, " | "), "quadric | euclidean");
  EXPECT_EQ(choice_names(mode, " or ", true), "\"qf+\" or \"qf\" or \"bf\"");
  for (const ParamRow* row : {&mode, &cluster_method})
    for (const ParamChoice& c : row->choices) {
      double v = -1;
      ASSERT_TRUE(parse_param(*row, format_param(*row, c.value), v).ok()) << c.name;
      EXPECT_EQ(v, c.value) << c.name;
    }
  double v = 0;
  EXPECT_FALSE(parse_param(mode, "QF", v).ok());
  EXPECT_FALSE(parse_param(mode, "quadric", v).ok());  // a cluster method's name
  EXPECT_FALSE(parse_param(cluster_method, "", v).ok());
  EXPECT_EQ(join_names({"a", "b"}, " | ", true), "\"a\" | \"b\"");
}

TEST(ParamTable, NamesAreUniqueAndEveryValueReadsBackAsText) {
  std::set<std::string> names;
  for (const ParamRow& row : param_table()) {
    EXPECT_TRUE(names.insert(row.name).second) << row.name << " twice";
    EXPECT_EQ(find_param(row.name), &row);
    const double v = test::other_value(row);
    Params p;
    row.set(p, v);
    EXPECT_EQ(row.get(p), v) << row.name;
    EXPECT_TRUE(check_param(row, v).ok()) << row.name;
    double back = -1;
    ASSERT_TRUE(parse_param(row, format_param(row, v), back).ok()) << row.name << " " << format_param(row, v);
    EXPECT_EQ(back, v) << row.name;
  }
  EXPECT_EQ(find_param("sigma_z"), nullptr);
  EXPECT_EQ(find_param("target_clusters")->flag(), "--target-clusters");
}

TEST(ParamTable, EnumsAreSpelledAsConfigsSpellThem) {
  const ParamRow& mode = *find_param("mode");
  EXPECT_EQ(choice_names(mode, " "), "qf+ qf bf");
  EXPECT_EQ(choice_names(*find_param("cluster_method"), " "), "quadric euclidean");
  EXPECT_EQ(choice_names(*find_param("cluster_geometry"), " "), "auto input filtered");
  EXPECT_EQ(format_param(mode, mode.get(Params{})), "qf+");
  double v = 0;
  ASSERT_TRUE(parse_param(mode, "qf+", v).ok());
  EXPECT_EQ(static_cast<FilterMethod>(static_cast<int>(v)), FilterMethod::kQuadricRefined);
  const Status bad = parse_param(mode, "qf_plus", v);
  EXPECT_NE(bad.message().find("mode must be one of qf+, qf, bf"), std::string::npos) << bad.message();
  EXPECT_FALSE(parse_param(*find_param("theta"), "0.5x", v).ok());
  EXPECT_FALSE(parse_param(*find_param("sticky_rings"), "2.5", v).ok());
  ASSERT_TRUE(parse_param(*find_param("track_ids"), "Off", v).ok());
  EXPECT_EQ(v, 0.0);
}

TEST(ParamTable, RangeMessagesNameTheRuleForZero) {
  const Status noise = check_param(*find_param("known_noise"), 11);
  EXPECT_NE(noise.message().find("known_noise must be in [0, 10] mean edge lengths (0 = estimated; got 11)"),
            std::string::npos)
      << noise.message();
  const Status b = check_param(*find_param("sigma_b"), -1);
  EXPECT_NE(b.message().find("sigma_b must be > 0 or 0 (0 = sigma_s / 2)"), std::string::npos) << b.message();
  Params p = clustering_params();
  p.clustering.target_clusters = 20'000'000;
  expect_rejected(p, "target_clusters");
  p.clustering.target_clusters = 0;
  p.clustering.sticky_rings = 65;
  expect_rejected(p, "sticky_rings");
}

}  // namespace
}  // namespace fq
