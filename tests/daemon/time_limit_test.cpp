// The engine time limit and stopping under load, against fqd as a child process: a frame
// whose parameters fit the neighbour-work budget but run past caps.engine_time_limit_s gets
// an error result that says so and is counted, and the next frame is served; SIGTERM with
// such a frame on the engine stops it after caps.stop_grace_s instead of waiting for it.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <random>
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

// A triangle soup of `n` triangles with edges of about 1 in the shell between radius 2 and 8
// (fast to cluster with narrow sigmas): its mean edge lets cluster-id tracking look 8 units
// around each vertex, where a denser previous frame (a unit sphere) lies whole.
Mesh soup_around_the_unit_sphere(uint32_t n) {
  std::mt19937 rng(9);
  std::normal_distribution<float> g(0.f, 1.f);
  std::uniform_real_distribution<float> radius(2.f, 8.f), jitter(-0.6f, 0.6f);
  Mesh m;
  for (uint32_t t = 0; t < n; ++t) {
    float c[3] = {g(rng), g(rng), g(rng)};
    const float scale = radius(rng) / std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2] + 1e-12f);
    for (int k = 0; k < 3; ++k) {
      for (float x : c) m.positions.push_back(x * scale + jitter(rng));
      m.triangles.push_back(3 * t + k);
    }
  }
  return m;
}

TEST(DaemonTimeLimit, SigtermWhileClusterIdsAreTrackedExitsWithinTheGrace) {
  // Before, tracking ran outside the limit and the stop, and its matcher looked at every
  // vertex of the sphere for each vertex of the soup after it (over a minute on the 2-core
  // development machine): SIGTERM waited for it. No time limit here: only the stop ends work.
  const std::string config = write_temp_file(
      "fqd_track_stop.toml", ops_config("[caps]\nengine_time_limit_s = 0\nstop_grace_s = 0.5\n"));
  FqdProcess fqd({"--config", config});
  ASSERT_TRUE(fqd.alive()) << "fqd did not start";
  DaemonHarness h(endpoints_of(fqd));
  client::FrameSpec s;
  s.compute = wire::CLUSTER;
  s.overrides.set_sigma_d(0.5f);
  s.overrides.set_sigma_q(0.5f);
  s.overrides.set_sigma_s(0.5f);
  s.overrides.set_sigma_b(0.25f);
  const Mesh soup = soup_around_the_unit_sphere(30000);  // 90,000 vertices
  // The soup's engine time, on a stream that does not track.
  s.stream_id = "probe";
  s.overrides.set_track_ids(false);
  h.send(soup, s, 1);
  const client::ReceivedResult probe = h.receive("probe");
  ASSERT_EQ(probe.header.status(), wire::OK) << probe.header.error();
  double engine_ms = 0;
  for (const auto& t : probe.header.timings())
    engine_ms += t.name() == "decode" || t.name() == "engine" ? t.ms() : 0.0;
  s.stream_id = "cam";
  s.overrides.set_track_ids(true);
  h.send(make_icosphere(7, 1.0f), s, 1);  // 163,842 vertices
  ASSERT_EQ(h.receive("cam").header.status(), wire::OK);
  h.send(soup, s, 2);
  // Decoded and clustered: its ids are being matched with the sphere's.
  std::this_thread::sleep_for(std::chrono::milliseconds(static_cast<int>(engine_ms) + 200));
  const auto t0 = Clock::now();
  const int status = fqd.stop();
  const double exit_s = std::chrono::duration<double>(Clock::now() - t0).count();
  EXPECT_EQ(status, 0);
  EXPECT_LT(exit_s, 0.5 + 1.0) << "fqd waited for cluster-id tracking";
  std::printf("fqd exited %.2f s after SIGTERM (the soup's decode and engine: %.0f ms)\n", exit_s, engine_ms);
}

}  // namespace
}  // namespace fq::test
