// fqd's decode queue under a burst, fqd as a child process with one decoder: large frames keep
// the decoder busy while 120 frames of 2 MiB arrive on 40 streams. Before, every one of them
// waited in fqd (its RSS grew by the burst); now the queue holds caps.max_queued_bytes and a
// full queue sheds the newest place of the connection holding most (here the one connection:
// the frame that came), so fqd's RSS stays within the bound while every frame still ends as a
// result or a counted drop.
#include <gtest/gtest.h>

#include <atomic>
#include <thread>
#include <zmq.hpp>

#include "clients/common/frame_sender.h"
#include "tests/daemon/daemon_harness.h"
#include "tests/daemon/fqd_process.h"
#include "tests/support/test_meshes.h"
#include "wire/header_codec.h"

namespace fq::test {
namespace {

constexpr size_t kMiB = 1 << 20;

TEST(Backpressure, ABurstWhileTheDecoderIsBusyStaysWithinTheQueueBound) {
  FqdProcess fqd(
      {"--config", write_temp_file("backpressure.toml",
                                   ops_config("[threads]\ndecode = 1\n[caps]\nmax_queued_frames = 8\n"
                                              "max_queued_bytes = 8388608\n"))});
  ASSERT_FALSE(fqd.endpoint("ingest").empty());
  // 163,842-vertex spheres keep the decoder busy; their parameters are refused after the
  // decode, so no frame waits for the engine.
  client::FrameSpec heavy_spec;
  heavy_spec.stream_id = "heavy";
  heavy_spec.overrides.set_theta(2.0f);
  heavy_spec.compute = wire::FILTER_AND_CLUSTER;
  std::vector<std::string> heavy;
  ASSERT_TRUE(client::build_frame(make_icosphere(7, 1.0f).view(), heavy_spec, 1, heavy).ok());
  // 2 MiB frames whose chunk is not Draco: admitted, and refused by the decoder at once (from a
  // producer without CURVE: dropped and counted `refused`).
  client::FrameSpec junk_spec;
  std::vector<std::string> junk;
  ASSERT_TRUE(client::build_frame(noisy_sphere().view(), junk_spec, 1, junk).ok());
  junk[2] = std::string(2 * kMiB, 'j');

  zmq::context_t ctx(1);
  zmq::socket_t push(ctx, zmq::socket_type::push);
  push.set(zmq::sockopt::linger, 0);
  push.connect(fqd.endpoint("ingest"));
  const size_t rss0 = rss_bytes(fqd.pid());
  std::atomic<size_t> peak{rss0};
  std::atomic<bool> sampling{true};
  std::thread sampler([&] {
    while (sampling) {
      peak = std::max<size_t>(peak, rss_bytes(fqd.pid()));
      std::this_thread::sleep_for(std::chrono::milliseconds(2));  // RSS samples, not ordering
    }
  });
  // 60 streams in all, within caps.max_streams.
  for (int i = 0; i < 20; ++i) client::send_parts(push, renamed_frame(heavy, "heavy" + std::to_string(i)));
  for (int i = 0; i < 120; ++i)
    client::send_parts(push, renamed_frame(junk, "junk" + std::to_string(i % 40)));
  // Every frame accounted for: each ended as an error result, refused, or superseded by a newer one.
  uint64_t done = 0;
  for (int wait = 0; wait < 600 && done < 140; ++wait) {
    done = 0;
    const ToolRun r = run_tool(FQCTL_PATH, {"--control", fqd.endpoint("control"), "counters", "--json"});
    for (const nlohmann::json& s :
         nlohmann::json::parse(r.output, nullptr, false).value("streams", nlohmann::json::array()))
      done += s.at("errors").get<uint64_t>() + s.at("refused").get<uint64_t>() +
              s.at("superseded").get<uint64_t>();
    if (done < 140) std::this_thread::sleep_for(std::chrono::milliseconds(100));  // polling fqd
  }
  sampling = false;
  sampler.join();
  EXPECT_EQ(done, 140u);
  // The queue's 8 MiB, the frame in the decoder with its mesh and Draco's own buffers, what
  // libzmq holds for the connection (at most 4 messages): well under the 240 MiB of the burst.
  EXPECT_LT(peak.load(), rss0 + 96 * kMiB)
      << "fqd RSS " << rss0 / kMiB << " -> peak " << peak / kMiB << " MiB";
  std::printf("fqd RSS %zu -> peak %zu MiB\n", rss0 / kMiB, peak.load() / kMiB);
  EXPECT_EQ(fqd.stop(), 0);
}

}  // namespace
}  // namespace fq::test
