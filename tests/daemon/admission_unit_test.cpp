// Stream-id admission, refusal log limiting and the neighbourhood work budget.
#include <gtest/gtest.h>

#include <string>

#include "daemon/config/echo_value.h"
#include "daemon/pipeline/log_limiter.h"
#include "daemon/pipeline/object_pool.h"
#include "daemon/pipeline/work_budget.h"
#include "daemon/stream/stream_admission.h"

namespace fq::daemon {
namespace {

TEST(StreamId, ValidUtf8WithoutControlCharactersIsAccepted) {
  EXPECT_TRUE(validate_stream_id("cam0", 128).ok());
  EXPECT_TRUE(validate_stream_id("Kamera-\xc3\xbc-\xe2\x82\xac-\xf0\x9f\x8e\xa5", 128).ok());  // ü € 🎥
}

TEST(StreamId, BadIdsAreRefusedWithAReadableMessage) {
  struct Case {
    std::string id;
    const char* words;
  };
  const Case cases[] = {
      {"", "empty"},
      {std::string(129, 'a'), "over the cap"},
      {"\xff\xfe"
       "cam",
       "not valid UTF-8"},
      {"\xc0\x80", "not valid UTF-8"},          // overlong NUL
      {"\xed\xa0\x80", "not valid UTF-8"},      // surrogate
      {"\xf4\x90\x80\x80", "not valid UTF-8"},  // above U+10FFFF
      {"\xe2\x82", "not valid UTF-8"},          // cut short
      {"cam\n0", "control character"},
      {std::string("ca\0m", 4), "control character"},
  };
  for (const Case& c : cases) {
    const Status s = validate_stream_id(c.id, 128);
    ASSERT_FALSE(s.ok()) << printable_id(c.id);
    EXPECT_NE(s.message().find(c.words), std::string::npos) << s.message();
    for (unsigned char ch : s.message()) EXPECT_TRUE(ch >= 0x20 && ch < 0x7f) << s.message();
  }
}

// Code points that a terminal, a log viewer or a browser acts on instead of showing: ESC was
// refused before as an ASCII control, the others were accepted as valid UTF-8. (\u escapes end
// after four digits: "\u202E0" is U+202E then '0'.)
TEST(StreamId, CodePointsThatActOnTheDisplayAreRefused) {
  const char* refused[] = {
      "cam\x1b[31m",   // ESC: a terminal colour sequence
      "cam\u009B31m",  // CSI as one code point
      "cam\u0085",     // next line
      "cam\u2028",     // line separator
      "cam\u2029",     // paragraph separator
      "cam\u202A",     // left-to-right embedding
      "cam\u202E0",    // right-to-left override
      "cam\u2066",     // left-to-right isolate
      "cam\u2069",     // pop directional isolate
  };
  for (const char* id : refused) {
    const Status s = validate_stream_id(id, 128);
    ASSERT_FALSE(s.ok()) << printable_id(id);
    EXPECT_NE(s.message().find("a line separator or a bidirectional formatting character (U+"),
              std::string::npos)
        << s.message();
  }
  // Their neighbours are ordinary characters.
  for (const char* id : {"cam\u00A0", "cam\u2027", "cam\u202F", "cam\u2065", "cam\u206A"})
    EXPECT_TRUE(validate_stream_id(id, 128).ok()) << printable_id(id);
}

TEST(StreamId, PrintableIdEscapesAndCutsWithTheSize) {
  EXPECT_EQ(printable_id("cam"), "cam");
  EXPECT_EQ(printable_id("\xff"
                         "a\\"),
            "\\xffa\\x5c");
  EXPECT_EQ(printable_id(std::string(100, 'x'), 8), "xxxxxxxx...(100 bytes)");
}

// A 64 MiB value echoed in a message or a log line costs a line of ordinary length.
TEST(EchoValue, AHugeValueBecomesABoundedPrefixWithItsSize) {
  const std::string huge(64u << 20, 'v');
  const std::string e = echo_value(huge);
  EXPECT_EQ(e, std::string(kEchoBytes, 'v') + "...(67108864 bytes)");
  EXPECT_EQ(echo_value("a\nb\x1b"), "a\\x0ab\\x1b");
}

TEST(StreamId, AllowListTakesExactIdsAndPrefixes) {
  const std::vector<std::string> allowed{"cam0", "studio-*"};
  EXPECT_TRUE(stream_allowed("anything", {}));
  EXPECT_TRUE(stream_allowed("cam0", allowed));
  EXPECT_FALSE(stream_allowed("cam01", allowed));
  EXPECT_TRUE(stream_allowed("studio-a", allowed));
  EXPECT_TRUE(stream_allowed("studio-", allowed));
  EXPECT_FALSE(stream_allowed("studio", allowed));
}

TEST(LogLimiter, PassesAFewASecondAndReportsTheRest) {
  LogLimiter l(2);
  uint64_t held = 99;
  int64_t t = 10'000'000'000;
  EXPECT_TRUE(l.allow(t, held));
  EXPECT_EQ(held, 0u);
  EXPECT_TRUE(l.allow(t + 1, held));
  for (int i = 0; i < 1000; ++i) EXPECT_FALSE(l.allow(t + 2 + i, held));
  EXPECT_TRUE(l.allow(t + 1'000'000'001, held));
  EXPECT_EQ(held, 1000u);
}

TEST(WorkBudget, NeighboursGrowWithTheSquareOfSigma) {
  EXPECT_NEAR(expected_neighbours(1.0), 14.51, 0.01);
  EXPECT_NEAR(expected_neighbours(10.0) / expected_neighbours(1.0), 100.0, 1e-9);
}

TEST(WorkBudget, HugeSigmaIsRefusedNamingItDefaultsPass) {
  Params p;  // defaults: filter only
  EXPECT_TRUE(check_work_budget(p, 4'000'000, 2e10).ok());
  p.cluster = true;
  EXPECT_TRUE(check_work_budget(p, 4'000'000, 2e10).ok());
  p.filtering.sigma_s = 1e4f;
  const Status s = check_work_budget(p, 35'000, 2e10);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("sigma_s"), std::string::npos) << s.message();
  EXPECT_NE(s.message().find("max_neighbour_work"), std::string::npos) << s.message();
}

// The budget reads the frame's plan (kernels/frame_plan.h): "qf+" alone runs no neighbourhood
// pass of sigma_s (before, it was counted as if it ran "qf"'s), and its refinement is counted:
// at the known noise, or at kBudgetNoise when the noise is estimated. At noise 0.5: 5 rounds of
// 6 face-normal passes (26 visits a vertex) and 10 vertex passes plus the fan setup (6 each),
// then the 4 passes of the tangential limit: 5 * (156 + 66) + 24 = 1134 visits per vertex.
TEST(WorkBudget, CountsTheRefinementFromThePlan) {
  EXPECT_DOUBLE_EQ(expected_refine_visits(0.5f), 1134.0);
  EXPECT_DOUBLE_EQ(expected_refine_visits(0.f), 26.0 + 6.0 * 3 + 24.0);  // 1 round, 1 normal, 2 vertex passes
  Params p;
  EXPECT_DOUBLE_EQ(expected_neighbour_work(p, 1000), 1134.0 * 1000);
  p.filtering.sigma_s = 1e4f;  // read by no pass of "qf+" alone
  EXPECT_TRUE(check_work_budget(p, 35'000, 2e10).ok());
  p.filtering.refine.known_noise = 10.f;  // 1601 rounds of 101 face-normal passes
  p.filtering.refine.strength = 1.f;
  const Status s = check_work_budget(p, 35'000, 2e10);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("known_noise"), std::string::npos) << s.message();
}

// Clustering on the filtered mesh runs the engine three times; before, the budget counted one
// run (the filter's sigma_b and sigma_s, the clustering's sigma_d twice).
TEST(WorkBudget, CountsTheClusteringGeometryRuns) {
  Params p;
  p.filtering.method = FilterMethod::kQuadric;  // sigma_s 1.5, sigma_b = sigma_n = 0.75
  p.cluster = true;                             // sigma_d 5
  const double one_run = expected_neighbours(0.75) + expected_neighbours(1.5) + 2 * expected_neighbours(5.0);
  EXPECT_NEAR(expected_neighbour_work(p, 1), one_run, 1e-9 * one_run);
  p.clustering.geometry = ClusterGeometry::kFiltered;
  const double frame = expected_neighbours(0.75) + expected_neighbours(1.5);
  const double geometry = frame + expected_neighbours(0.75);  // constrained: the normals within sigma_n
  const double clusters =
      expected_neighbours(0.375) + expected_neighbours(0.75) + 2 * expected_neighbours(5.0);
  EXPECT_NEAR(expected_neighbour_work(p, 1), frame + geometry + clusters, 1e-9 * one_run);
}

}  // namespace
}  // namespace fq::daemon

namespace fq::daemon {
namespace {

ObjectPool<std::vector<float>> vector_pool() {
  return ObjectPool<std::vector<float>>(
      8, [](const std::vector<float>& v) { return v.capacity() * sizeof(float); },
      [](const std::vector<float>& v) { return v.size() * sizeof(float); });
}

TEST(ObjectPool, KeepsBuffersOfSteadyFramesAndFreesOversizedOnes) {
  auto pool = vector_pool();
  std::vector<float> steady(1 << 20);
  pool.release(std::move(steady));
  EXPECT_EQ(pool.kept(), 1u);
  std::vector<float> reused = pool.acquire();
  EXPECT_GE(reused.capacity(), size_t(1) << 20) << "a kept buffer comes back with its capacity";
  reused.resize(1000);  // a small frame in a huge frame's buffer
  pool.release(std::move(reused));
  EXPECT_EQ(pool.kept(), 0u) << "a buffer holding far more than it used is freed";
}

TEST(ObjectPool, TrimFreesEverythingAfterIdleTime) {
  auto pool = vector_pool();
  (void)pool.acquire(1'000);
  pool.release(std::vector<float>(1000));
  pool.release(std::vector<float>(1000));
  pool.trim(2'000, 5'000);
  EXPECT_EQ(pool.kept(), 2u) << "not idle long enough";
  pool.trim(10'000, 5'000);
  EXPECT_EQ(pool.kept(), 0u);
}

}  // namespace
}  // namespace fq::daemon
