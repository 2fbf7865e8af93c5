// A subscriber that connects and never reads, beside one that reads, while results of a few
// MB flow: fqd (a child process) queues at most caps.max_subscriber_results (plus one being
// written) for the slow one, counts the results it missed, and the reading one gets every
// result.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <string>
#include <thread>
#include <vector>
#include <zmq.hpp>

#include "eval/noise.h"
#include "tests/daemon/daemon_harness.h"
#include "tests/daemon/fqd_process.h"
#include "tests/support/test_meshes.h"

namespace fq::test {
namespace {

constexpr size_t kMiB = 1u << 20;
constexpr size_t kMaxSubscriberResults = 2;

TEST(DaemonSlowSubscriber, QueuesAreBoundedInBytesAndDropsAreCounted) {
  // Results of ~1 MB (22-bit positions of 163,842 vertices; the plain filter with a small
  // neighbourhood: little engine time).
  const std::string config = write_temp_file(
      "fqd_slow_subscriber.toml",
      ops_config("[caps]\nmax_subscriber_results = " + std::to_string(kMaxSubscriberResults) +
                 "\n[defaults.filter]\nmethod = \"qf\"\n[defaults.output]\nposition_bits = 22\n"));
  FqdProcess fqd({"--config", config});
  ASSERT_TRUE(fqd.alive()) << "fqd did not start";
  DaemonHarness h(
      daemon::BoundEndpoints{fqd.endpoint("ingest"), fqd.endpoint("publish"), fqd.endpoint("control"), ""});

  Mesh mesh = make_icosphere(7, 1.0f);  // 163,842 vertices
  add_gaussian_noise(mesh, 0.05, 3);
  client::FrameSpec spec;
  spec.stream_id = "big";
  spec.compute = wire::FILTER;
  spec.overrides.set_sigma_s(0.5f);  // little engine work: the test is about the results
  std::vector<std::string> parts;
  ASSERT_TRUE(client::build_frame(mesh.view(), spec, 0, parts).ok());
  size_t result_bytes = 0;
  auto round_trip = [&](uint64_t seq) {
    client::restamp_frame(parts, seq);
    h.send_parts(parts);
    const client::ReceivedResult r = h.receive("big");
    EXPECT_EQ(r.header.status(), wire::OK) << r.header.error();
    EXPECT_EQ(r.header.sequence(), seq) << "the reading subscriber missed a result";
    size_t bytes = 0;
    for (const zmq::message_t& c : r.chunks) bytes += c.size();
    result_bytes = std::max(result_bytes, bytes);
  };
  for (uint64_t seq = 0; seq < 3; ++seq) round_trip(seq);  // warm-up: pools, allocator
  ASSERT_GT(result_bytes, 768u << 10);
  // The same frames without the slow subscriber first: what fqd's pools and the allocator's
  // arenas keep for this stream (fqd hands free pages back only once frames stop or a pool
  // shrinks) is then part of the base, and the bound below is what the slow subscriber adds.
  constexpr uint64_t kFrames = 60;
  size_t base = rss_bytes(fqd.pid());
  for (uint64_t seq = 3; seq < 3 + kFrames; ++seq) {
    round_trip(seq);
    base = std::max(base, rss_bytes(fqd.pid()));
  }

  {
    // Never reads; its own buffers are kept tiny, so that what it does not take stays in fqd.
    zmq::context_t ctx(1);
    zmq::socket_t slow(ctx, zmq::socket_type::sub);
    slow.set(zmq::sockopt::rcvhwm, 1);
    slow.set(zmq::sockopt::rcvbuf, 64 << 10);
    slow.set(zmq::sockopt::linger, 0);
    slow.set(zmq::sockopt::subscribe, "big");
    slow.connect(fqd.endpoint("publish"));
    std::this_thread::sleep_for(std::chrono::milliseconds(300));  // its subscription reaches fqd

    size_t peak = base;
    for (uint64_t seq = 3 + kFrames; seq < 3 + 2 * kFrames; ++seq) {
      round_trip(seq);
      peak = std::max(peak, rss_bytes(fqd.pid()));
    }
    // Queued for the slow subscriber: at most max_subscriber_results results plus the one
    // ZeroMQ is writing (the kernel's send buffer is not fqd's RSS); 24 MiB more for
    // allocator slack. With ZeroMQ's default mark (1000 results) fqd kept every result:
    // about kFrames x 1 MB.
    const size_t bound = (kMaxSubscriberResults + 1) * result_bytes + 24 * kMiB;
    EXPECT_LT(peak, base + bound) << "fqd RSS " << base / kMiB << " -> " << peak / kMiB << " MiB, results of "
                                  << result_bytes / 1024 << " KiB";
    const wire::StreamCounters c = h.counters("big");
    EXPECT_EQ(c.frames_out(), 3 + 2 * kFrames);
    // ZeroMQ stops offering results to a full subscriber until it has read, so a subscriber
    // that never reads overflows once.
    EXPECT_GE(c.subscriber_overflows(), 1u) << "the slow subscriber's overflow is counted";
    std::printf("fqd RSS %zu -> peak %zu MiB over %llu results of %zu KiB; subscriber_overflows %llu\n",
                base / kMiB, peak / kMiB, static_cast<unsigned long long>(kFrames), result_bytes / 1024,
                static_cast<unsigned long long>(c.subscriber_overflows()));
  }
}

}  // namespace
}  // namespace fq::test
