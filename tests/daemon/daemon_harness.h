// A daemon started in-process on ephemeral 127.0.0.1 ports with the CPU engine, and the
// three client sockets a test talks to it with (PUSH frames, SUB results, REQ control).
#pragma once

#include <chrono>
#include <deque>
#include <map>
#include <memory>
#include <string>
#include <vector>
#include <zmq.hpp>

#include "clients/common/control_client.h"
#include "clients/common/curve_client.h"
#include "clients/common/frame_sender.h"
#include "clients/common/result_receiver.h"
#include "daemon/config/config.h"
#include "daemon/daemon.h"

namespace fq::test {

/// Defaults for tests: CPU engine on 2 threads, every endpoint tcp://127.0.0.1:*, a
/// generous budget (so nothing is late or stale unless a test asks), log level warn.
daemon::DaemonConfig test_config();

/// Noisy icosphere (642 vertices) used by most daemon tests.
Mesh noisy_sphere(uint64_t seed = 7, int subdivisions = 3);

/// A frame spec for `stream`, everything else as the stream's settings say.
client::FrameSpec frame_spec(const std::string& stream);

/// `parts` (a built frame) renamed to `stream`: topic and header.
std::vector<std::string> renamed_frame(std::vector<std::string> parts, const std::string& stream);

/// Resident memory of process `pid` (0: this process) from /proc, in bytes; 0 when unknown.
size_t rss_bytes(int pid = 0);

class DaemonHarness {
 public:
  /// Starts a daemon in this process and connects to it.
  explicit DaemonHarness(daemon::DaemonConfig config = test_config(), client::CurveClientOptions curve = {});
  /// Connects to a daemon running elsewhere (e.g. a child process).
  explicit DaemonHarness(const daemon::BoundEndpoints& endpoints);
  ~DaemonHarness();

  /// The in-process daemon (null when connected to one elsewhere).
  daemon::Daemon* daemon() { return daemon_.get(); }

  void send_parts(const std::vector<std::string>& parts);
  /// Encodes and sends one frame (the test fails on an encode error).
  void send(const Mesh& mesh, const client::FrameSpec& spec, uint64_t sequence);
  /// The next result on `stream`; results of other streams that come first are kept for
  /// their own receive() (probe results are dropped). Fails the test after 60 s.
  client::ReceivedResult receive(const std::string& stream);
  /// Sends a probe frame and reads every result up to the probe's own, dropping them: fqd
  /// publishes in admission order, so every result of a frame sent before has then been
  /// published (or dropped for this subscriber). Fails the test after 60 s.
  void sync_results();
  /// receive() plus decode and consumer checks (the test fails when they fail). A
  /// POSITIONS result gets the faces of `input` when given (none otherwise).
  client::ReceivedResult receive_decoded(const std::string& stream, const Mesh* input = nullptr);

  /// One control round trip; the reply as received (ok may be false).
  wire::ControlReply control(const wire::ControlRequest& request);
  /// The counters of one stream (the test fails when it is unknown).
  wire::StreamCounters counters(const std::string& stream);

 private:
  void connect(const daemon::BoundEndpoints& e);
  void wait_for_subscription();
  bool probe(int attempts, std::chrono::milliseconds window);

  std::unique_ptr<daemon::Daemon> daemon_;
  client::CurveClientOptions curve_;
  zmq::context_t ctx_{1};
  zmq::socket_t push_, sub_, req_;
  std::map<std::string, std::deque<client::ReceivedResult>> pending_;
  uint64_t probe_sequence_ = 0;  ///< the last probe frame's sequence number
};

}  // namespace fq::test
