// The engine time limit and stopping under load, against fqd as a child process: a frame
// whose parameters fit the neighbour-work budget but run past caps.engine_time_limit_s gets
// an error result that says so and is counted, and the next frame is served; SIGTERM with
// such a frame on the engine stops it after caps.stop_grace_s instead of waiting for it.
#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <thread>

#include "eval/noise.h"
#include "io/ply_reader.h"
#include "tests/daemon/daemon_harness.h"
#include "tests/daemon/fqd_process.h"
#include "tests/support/test_meshes.h"

namespace fq::test {
namespace {

using Clock = std::chrono::steady_clock;

daemon::BoundEndpoints endpoints_of(const FqdProcess& fqd) {
  return {fqd.endpoint("ingest"), fqd.endpoint("publish"), fqd.endpoint("control"), ""};
}

// A neighbourhood wider than the mesh (sigmas in mean edges): every vertex visits every
// other in each pass, far under caps.max_neighbour_work's estimate for an unbounded surface.
client::FrameSpec wide_spec(const std::string& stream, float sigma) {
  client::FrameSpec s;
  s.stream_id = stream;
  s.compute = wire::FILTER_AND_CLUSTER;
  s.overrides.set_sigma_s(sigma);
  s.overrides.set_sigma_d(sigma);
  return s;
}

TEST(DaemonTimeLimit, AFrameOverTheLimitGetsAnErrorAndTheNextIsServed) {
  const std::string config =
      write_temp_file("fqd_time_limit.toml", ops_config("[caps]\nengine_time_limit_s = 0.5\n"));
  FqdProcess fqd({"--config", config});
  ASSERT_TRUE(fqd.alive()) << "fqd did not start";
  DaemonHarness h(endpoints_of(fqd));
  Mesh fandisk;
  ASSERT_TRUE(io::read_ply(std::string(FQ_SOURCE_DIR) + "/data/fandisk.ply", fandisk).ok());
  // Seconds of engine time on one thread (6,475 vertices, each pass 6,475 x 6,475 visits).
  h.send(fandisk, wide_spec("cam", 40.f), 1);
  const client::ReceivedResult stopped = h.receive("cam");
  EXPECT_EQ(stopped.header.status(), wire::ERROR);
  EXPECT_EQ(stopped.header.sequence(), 1u);
  EXPECT_NE(stopped.header.error().find("time_limit"), std::string::npos) << stopped.header.error();
  EXPECT_NE(stopped.header.error().find("caps.engine_time_limit_s = 0.5 s"), std::string::npos)
      << stopped.header.error();
  // The next frame (a small one: milliseconds, far inside the limit) is served.
  client::FrameSpec plain;
  plain.stream_id = "cam";
  h.send(noisy_sphere(), plain, 2);
  const client::ReceivedResult served = h.receive("cam");
  EXPECT_EQ(served.header.status(), wire::OK) << served.header.error();
  EXPECT_EQ(served.header.sequence(), 2u);
  const wire::StreamCounters c = h.counters("cam");
  EXPECT_EQ(c.time_limited(), 1u);
  EXPECT_EQ(c.errors(), 1u);
  EXPECT_EQ(c.frames_out(), 1u);
}

TEST(DaemonTimeLimit, SigtermStopsTheFrameOnTheEngineAfterTheGrace) {
  // No time limit: only the stop ends the frame. Before, fqd finished it first (over a
  // minute on the 2-core development machine).
  const std::string config = write_temp_file(
      "fqd_stop_grace.toml", ops_config("[caps]\nengine_time_limit_s = 0\nstop_grace_s = 0.5\n"));
  FqdProcess fqd({"--config", config});
  ASSERT_TRUE(fqd.alive()) << "fqd did not start";
  DaemonHarness h(endpoints_of(fqd));
  Mesh mesh = make_icosphere(6, 1.0f);  // 40,962 vertices
  add_gaussian_noise(mesh, 0.2, 5);
  h.send(mesh, wide_spec("cam", 100.f), 7);
  wire::ControlRequest q;
  q.mutable_get_counters()->set_stream_id("cam");
  const auto deadline = Clock::now() + std::chrono::seconds(60);
  while (!h.control(q).ok() && Clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));  // until fqd has received it
  std::this_thread::sleep_for(std::chrono::seconds(1));         // decoded, on the engine
  const auto t0 = Clock::now();
  const int status = fqd.stop();  // SIGTERM; fqd is killed if it has not exited within 60 s
  const double exit_s = std::chrono::duration<double>(Clock::now() - t0).count();
  EXPECT_EQ(status, 0);
  // Generous for a loaded machine: the grace, then at most one chunk of one loop.
  EXPECT_LT(exit_s, 10.0) << "fqd waited for the frame instead of stopping it";
  const client::ReceivedResult r = h.receive("cam");
  EXPECT_EQ(r.header.status(), wire::ERROR);
  EXPECT_EQ(r.header.sequence(), 7u);
  EXPECT_NE(r.header.error().find("fqd is stopping"), std::string::npos) << r.header.error();
  std::printf("fqd exited %.2f s after SIGTERM with the frame on the engine\n", exit_s);
}

}  // namespace
}  // namespace fq::test
