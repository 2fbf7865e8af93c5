// Scale-out by topic sharding: two fqd processes on 127.0.0.1 SUB-connect to one producer's
// PUB socket and share four streams by [ingest] streams. Every stream's results come from
// exactly one fqd, and none is lost: each frame sent after both subscribed has one result.
#include <gtest/gtest.h>

#include <chrono>
#include <map>
#include <set>

#include "clients/common/frame_sender.h"
#include "clients/common/result_receiver.h"
#include "tests/daemon/daemon_harness.h"
#include "tests/daemon/fqd_process.h"

namespace fq::test {
namespace {

const std::vector<std::string> kStreams{"s0", "s1", "s2", "s3"};

std::string shard_config(const std::string& producer, const std::vector<std::string>& streams) {
  std::string list;
  for (const std::string& s : streams) list += (list.empty() ? "\"" : ", \"") + s + "\"";
  return ops_config("[ingest]\nconnect = [\"" + producer + "\"]\nstreams = [" + list + "]\n");
}

struct Shard {
  std::unique_ptr<FqdProcess> fqd;
  zmq::socket_t sub;
};

class ShardTest : public testing::Test {
 protected:
  zmq::context_t ctx_{1};
  zmq::socket_t pub_{ctx_, zmq::socket_type::pub};
  std::vector<Shard> shards_;
  Mesh mesh_ = noisy_sphere();

  void start(const std::vector<std::vector<std::string>>& assignment) {
    pub_.set(zmq::sockopt::sndhwm, 100000);
    pub_.bind("tcp://127.0.0.1:*");
    const std::string producer = pub_.get(zmq::sockopt::last_endpoint);
    for (size_t i = 0; i < assignment.size(); ++i) {
      Shard s;
      const std::string name = "shard" + std::to_string(i) + ".toml";
      s.fqd = std::make_unique<FqdProcess>(
          std::vector<std::string>{"--config", write_temp_file(name, shard_config(producer, assignment[i]))});
      ASSERT_FALSE(s.fqd->endpoint("publish").empty()) << "fqd " << i << " did not start";
      s.sub = zmq::socket_t(ctx_, zmq::socket_type::sub);
      s.sub.set(zmq::sockopt::subscribe, "");
      s.sub.set(zmq::sockopt::rcvtimeo, 100);
      s.sub.connect(s.fqd->endpoint("publish"));
      shards_.push_back(std::move(s));
    }
  }

  void send(const std::string& stream, uint64_t sequence) {
    client::FrameSpec spec;
    spec.stream_id = stream;
    std::vector<std::string> parts;
    ASSERT_TRUE(client::build_frame(mesh_.view(), spec, sequence, parts).ok());
    client::send_parts(pub_, parts);
  }

  // Receives from every shard until `done` or 60 s; calls `on(shard, result)` for each.
  template <class On, class Done>
  void receive_until(On on, Done done) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (!done() && std::chrono::steady_clock::now() < deadline) {
      for (size_t i = 0; i < shards_.size(); ++i) {
        client::ReceivedResult r;
        const StatusOr<bool> got = client::receive_result(shards_[i].sub, r);
        if (got.ok() && *got) on(i, r);
      }
    }
  }
};

TEST_F(ShardTest, TwoDaemonsShareFourStreamsEachServedByOneNoneLost) {
  start({{"s0", "s1"}, {"s2", "s3"}});
  // Warm-up: PUB drops frames until each fqd's subscription has arrived, so send on every
  // stream until every stream has a result (these frames are not part of the count).
  std::set<std::string> warm;
  for (uint64_t seq = 1000; warm.size() < kStreams.size() && seq < 1300; ++seq) {
    for (const std::string& s : kStreams)
      if (!warm.count(s)) send(s, seq);
    const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(200);
    receive_until([&](size_t, const client::ReceivedResult& r) { warm.insert(r.topic); },
                  [&] { return std::chrono::steady_clock::now() > until; });
  }
  ASSERT_EQ(warm.size(), kStreams.size()) << "a stream never got a result";
  // Let the warm-up results drain so that they are not mistaken for counted ones.
  const auto drain = std::chrono::steady_clock::now() + std::chrono::seconds(3);
  receive_until([](size_t, const client::ReceivedResult&) {},
                [&] { return std::chrono::steady_clock::now() > drain; });

  // Counted frames: one per stream at a time, each waited for, so nothing is superseded.
  // "s1x" is assigned to no fqd; its topic has the prefix "s1", which ZeroMQ delivers to the
  // fqd subscribed to "s1": that fqd must ignore it (see the stream lists at the end).
  std::map<std::string, std::set<size_t>> served_by;
  std::map<std::string, std::multiset<uint64_t>> got;
  constexpr uint64_t kFrames = 5;
  for (uint64_t seq = 0; seq < kFrames; ++seq) {
    for (const std::string& s : kStreams) send(s, seq);
    send("s1x", seq);
    size_t results = 0;
    receive_until(
        [&](size_t shard, const client::ReceivedResult& r) {
          served_by[r.topic].insert(shard);
          if (r.header.sequence() >= 1000) return;  // a late warm-up result
          EXPECT_NE(r.header.status(), wire::ERROR) << r.header.error();
          got[r.topic].insert(r.header.sequence());
          ++results;
        },
        [&] { return results == kStreams.size(); });
  }
  for (const std::string& s : kStreams) {
    EXPECT_EQ(served_by[s], std::set<size_t>{s < "s2" ? 0u : 1u}) << s;
    std::multiset<uint64_t> want;
    for (uint64_t q = 0; q < kFrames; ++q) want.insert(q);
    EXPECT_EQ(got[s], want) << s;
  }
  // Each fqd knows only its own streams.
  for (size_t i = 0; i < shards_.size(); ++i) {
    const ToolRun r = run_tool(FQCTL_PATH, {"--control", shards_[i].fqd->endpoint("control"), "streams"});
    EXPECT_EQ(r.output, i == 0 ? "s0\ns1\n" : "s2\ns3\n");
    EXPECT_EQ(shards_[i].fqd->stop(), 0);
  }
}

}  // namespace
}  // namespace fq::test
