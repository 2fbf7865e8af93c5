// A stream's temporal history lives in its Stream (daemon/stream/stream_history.h): frames in arrival
// order update it, a frame that finished after a newer one runs alone, a frame without
// temporal filtering drops it, and it goes with the stream. Real CPU engine, no sockets.
#include "daemon/stream/stream_history.h"

#include <gtest/gtest.h>

#include <memory>

#include "daemon/stream/stream_registry.h"
#include "eval/noise.h"
#include "kernels/cpu_engine.h"
#include "tests/support/test_meshes.h"

namespace fq::daemon {
namespace {

Params temporal_params(float temporal) {
  Params p;  // qf+, the default filter
  p.filtering.temporal = temporal;
  return p;
}

Mesh noisy_sphere(uint64_t seed) {
  Mesh m = test::make_icosphere(3);
  add_gaussian_noise(m, 0.2, seed);
  return m;
}

Status run(Stream& s, uint64_t arrival, const Params& p, Engine& e, const Mesh& m, FrameResult& out) {
  return with_history(s, arrival, p, e, [&] { return e.process(m.view(), p, out); });
}

TEST(StreamHistory, FramesInOrderKeepTheStreamsLastResultAndALateOneRunsAlone) {
  CpuEngine engine(2);
  Stream s("cam", StreamSettings{}, 0);
  const Mesh first = noisy_sphere(1), second = noisy_sphere(2);
  FrameResult r;
  ASSERT_TRUE(run(s, 5, temporal_params(0.75f), engine, first, r).ok());
  EXPECT_EQ(s.temporal.history.frames, 1u);
  EXPECT_EQ(s.temporal.last_arrival, 5u);
  ASSERT_TRUE(run(s, 7, temporal_params(0.75f), engine, second, r).ok());
  EXPECT_EQ(s.temporal.history.frames, 2u);
  EXPECT_GT(r.prior_coverage, 0.5f) << "the second frame found the first's result";
  // Arrival 6 finished after 7: filtered alone, the history stays the newer frame's.
  FrameResult late;
  ASSERT_TRUE(run(s, 6, temporal_params(0.75f), engine, first, late).ok());
  EXPECT_EQ(late.prior_coverage, 0.f);
  EXPECT_EQ(s.temporal.history.frames, 2u);
  EXPECT_EQ(s.temporal.last_arrival, 7u);
}

TEST(StreamHistory, AFrameWithoutTemporalFilteringDropsTheHistory) {
  CpuEngine engine(2);
  Stream s("cam", StreamSettings{}, 0);
  const Mesh m = noisy_sphere(1);
  FrameResult r;
  ASSERT_TRUE(run(s, 1, temporal_params(0.75f), engine, m, r).ok());
  ASSERT_FALSE(s.temporal.history.empty());
  ASSERT_TRUE(run(s, 2, temporal_params(0.f), engine, m, r).ok());
  EXPECT_TRUE(s.temporal.history.empty());
  EXPECT_EQ(s.temporal.history.positions.capacity(), 0u) << "its memory is given back";
  EXPECT_EQ(s.temporal.last_arrival, 0u);
}

// Expiry needs no step of its own: the history is the Stream's, freed with it.
TEST(StreamHistory, TheHistoryGoesWithAnExpiredStream) {
  DaemonConfig c;
  StreamRegistry registry(c);
  CpuEngine engine(2);
  const int64_t now = wall_ns();
  std::weak_ptr<Stream> watch;
  {
    const StreamPtr s = registry.admit("cam", now);
    ASSERT_NE(s, nullptr);
    watch = s;
    FrameResult r;
    ASSERT_TRUE(run(*s, 1, temporal_params(0.75f), engine, noisy_sphere(1), r).ok());
    ASSERT_FALSE(s->temporal.history.empty());
  }
  EXPECT_EQ(registry.expire_idle(now + 10'000'000'000, 1.0), std::vector<std::string>{"cam"});
  EXPECT_TRUE(watch.expired());
  const StreamPtr again = registry.admit("cam", now + 11'000'000'000);
  EXPECT_TRUE(again->temporal.history.empty()) << "the id comes back without the old history";
}

}  // namespace
}  // namespace fq::daemon
