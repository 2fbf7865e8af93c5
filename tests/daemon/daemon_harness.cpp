#include "tests/daemon/daemon_harness.h"

#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <string>

#include "eval/noise.h"
#include "tests/support/test_meshes.h"
#include "wire/header_codec.h"

namespace fq::test {

daemon::DaemonConfig test_config() {
  daemon::DaemonConfig c;
  c.endpoints = {"tcp://127.0.0.1:*", "tcp://127.0.0.1:*", "tcp://127.0.0.1:*"};
  c.engine.kind = EngineKind::kCpu;
  c.engine.cpu_threads = 2;
  c.log_level = "warn";
  c.defaults.budget_ms = 60'000.0;
  c.defaults.params.cluster = true;
  return c;
}

size_t rss_bytes(int pid) {
  std::ifstream in(pid == 0 ? std::string("/proc/self/status") : "/proc/" + std::to_string(pid) + "/status");
  std::string key;
  while (in >> key) {
    if (key == "VmRSS:") {
      size_t kb = 0;
      in >> kb;
      return kb * 1024;
    }
    std::getline(in, key);
  }
  return 0;
}

client::FrameSpec frame_spec(const std::string& stream) {
  client::FrameSpec s;
  s.stream_id = stream;
  return s;
}

std::vector<std::string> renamed_frame(std::vector<std::string> parts, const std::string& stream) {
  wire::FrameHeader h;
  EXPECT_TRUE(wire::parse_frame_header(parts[1], h).ok());
  h.set_stream_id(stream);
  parts[0] = stream;
  parts[1] = h.SerializeAsString();
  return parts;
}

Mesh noisy_sphere(uint64_t seed, int subdivisions) {
  Mesh m = make_icosphere(subdivisions, 1.0f);
  add_gaussian_noise(m, 0.2, seed);
  return m;
}

DaemonHarness::DaemonHarness(daemon::DaemonConfig config, client::CurveClientOptions curve)
    : daemon_(std::make_unique<daemon::Daemon>(std::move(config))), curve_(std::move(curve)) {
  const Status s = daemon_->start();
  if (!s.ok()) {
    ADD_FAILURE() << "daemon did not start: " << s.message();
    return;
  }
  connect(daemon_->endpoints());
}

DaemonHarness::DaemonHarness(const daemon::BoundEndpoints& endpoints) { connect(endpoints); }

void DaemonHarness::connect(const daemon::BoundEndpoints& e) {
  push_ = zmq::socket_t(ctx_, zmq::socket_type::push);
  sub_ = zmq::socket_t(ctx_, zmq::socket_type::sub);
  req_ = zmq::socket_t(ctx_, zmq::socket_type::req);
  for (zmq::socket_t* s2 : {&push_, &sub_, &req_}) {
    s2->set(zmq::sockopt::linger, 0);
    const Status s = client::apply_curve_client(*s2, curve_);
    if (!s.ok()) ADD_FAILURE() << s.message();
  }
  sub_.set(zmq::sockopt::subscribe, "");
  sub_.set(zmq::sockopt::rcvhwm, 100000);
  push_.connect(e.ingest);
  sub_.connect(e.publish);
  req_.connect(e.control);
  wait_for_subscription();
}

DaemonHarness::~DaemonHarness() {
  if (daemon_) daemon_->stop();
  push_.close();
  sub_.close();
  req_.close();
}

// Sends probe frames, one per `window`, until the result of one of them comes back (at most
// `attempts` of them); the socket's receive timeout is 60 s again afterwards.
bool DaemonHarness::probe(int attempts, std::chrono::milliseconds window) {
  const Mesh probe = make_icosphere(0, 1.0f);
  client::FrameSpec spec;
  spec.stream_id = "__probe";
  spec.compute = wire::FILTER;
  const uint64_t first = probe_sequence_ + 1;
  sub_.set(zmq::sockopt::rcvtimeo, 100);
  bool answered = false;
  for (int attempt = 0; attempt < attempts && !answered; ++attempt) {
    send(probe, spec, ++probe_sequence_);
    const auto end = std::chrono::steady_clock::now() + window;
    while (!answered && std::chrono::steady_clock::now() < end) {
      client::ReceivedResult r;
      if (client::timed_out(client::receive_result(sub_, r))) continue;
      answered = r.topic == "__probe" && r.header.sequence() >= first;
    }
  }
  sub_.set(zmq::sockopt::rcvtimeo, 60'000);
  return answered;
}

// A SUB socket only sees messages published after its subscription reached the PUB side:
// once a probe comes back, every later result is seen (later probe results may still come;
// receive() skips them).
void DaemonHarness::wait_for_subscription() {
  if (!probe(600, std::chrono::milliseconds(100)))
    ADD_FAILURE() << "no probe result came back: the subscription never became active";
}

void DaemonHarness::send_parts(const std::vector<std::string>& parts) { client::send_parts(push_, parts); }

void DaemonHarness::send(const Mesh& mesh, const client::FrameSpec& spec, uint64_t sequence) {
  std::vector<std::string> parts;
  const Status s = client::build_frame(mesh.view(), spec, sequence, parts);
  ASSERT_TRUE(s.ok()) << s.message();
  send_parts(parts);
}

client::ReceivedResult DaemonHarness::receive(const std::string& stream) {
  client::ReceivedResult r;
  if (auto it = pending_.find(stream); it != pending_.end() && !it->second.empty()) {
    r = std::move(it->second.front());
    it->second.pop_front();
    if (it->second.empty()) pending_.erase(it);  // tests with thousands of streams stay flat
    return r;
  }
  for (;;) {
    const StatusOr<bool> got = client::receive_result(sub_, r);
    if (client::timed_out(got)) {
      ADD_FAILURE() << "no result on stream '" << stream << "' within 60 s";
      return r;
    }
    EXPECT_TRUE(got.ok()) << got.status().message();
    if (r.topic == stream) return r;
    if (r.topic != "__probe") pending_[r.topic].push_back(std::move(r));
  }
}

// A probe's result can itself be dropped for this subscriber when it follows a burst that
// filled fqd's queue for it: then the next probe goes.
void DaemonHarness::sync_results() {
  if (!probe(60, std::chrono::seconds(1))) ADD_FAILURE() << "no probe result within 60 s";
}

client::ReceivedResult DaemonHarness::receive_decoded(const std::string& stream, const Mesh* input) {
  client::ReceivedResult r = receive(stream);
  EXPECT_NE(r.header.status(), wire::ERROR) << r.header.error();
  Status s = client::decode_result(r, 2, input ? &input->triangles : nullptr);
  EXPECT_TRUE(s.ok()) << s.message();
  s = client::check_result(r);
  EXPECT_TRUE(s.ok()) << s.message();
  return r;
}

wire::ControlReply DaemonHarness::control(const wire::ControlRequest& request) {
  wire::ControlReply reply;
  const Status s = client::control_call(req_, request, reply, 60'000);
  if (s.code() == StatusCode::kUnavailable) ADD_FAILURE() << s.message();
  return reply;
}

wire::StreamCounters DaemonHarness::counters(const std::string& stream) {
  wire::ControlRequest q;
  q.mutable_get_counters()->set_stream_id(stream);
  const wire::ControlReply r = control(q);
  EXPECT_TRUE(r.ok()) << r.error();
  if (r.counters_size() != 1) {
    ADD_FAILURE() << "expected the counters of one stream";
    return {};
  }
  return r.counters(0);
}

}  // namespace fq::test
