// Parameter validation (core/params.h): every bad value is an kInvalidArgument whose
// message names the parameter, both from validate() and from the engine, and the engine
// stays usable afterwards.
#include "core/params.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "kernels/cpu_engine.h"
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
  EXPECT_NE(s.message().find(name), std::string::npos) << "message '" << s.message() << "' does not name " << name;
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
  EXPECT_EQ(method_names<FilterMethod>(), (std::vector<std::string>{"qf+", "qf", "bf"}));
  EXPECT_EQ(method_names<ClusterMethod>(), (std::vector<std::string>{"quadric", "euclidean"}));
  for (FilterMethod m : {FilterMethod::kQuadricRefined, FilterMethod::kQuadric, FilterMethod::kBilateral})
    EXPECT_EQ(parse_method<FilterMethod>(method_name(m)), m);
  for (ClusterMethod m : {ClusterMethod::kQuadric, ClusterMethod::kEuclidean})
    EXPECT_EQ(parse_method<ClusterMethod>(method_name(m)), m);
  EXPECT_EQ(parse_method<FilterMethod>("QF"), std::nullopt);
  EXPECT_EQ(parse_method<FilterMethod>("quadric"), std::nullopt);  // a cluster method's name
  EXPECT_EQ(parse_method<ClusterMethod>(""), std::nullopt);
  EXPECT_EQ(join_names(method_names<FilterMethod>()), "qf+ or qf or bf");
  EXPECT_EQ(join_names(method_names<ClusterMethod>(), " | "), "quadric | euclidean");
  EXPECT_EQ(join_names(method_names<FilterMethod>(), " or ", true), "\"qf+\" or \"qf\" or \"bf\"");
}

}  // namespace
}  // namespace fq
