// fqd's results of stream "cam" (python/examples/consumer.py in C++; docs/PROTOCOL.md), and how far
// each lies from producer.cpp's torus. Exits 0 after frame LAST's result (default 4), 1 on an error.
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "clients/common/peer_monitor.h"
#include "clients/common/result_receiver.h"

int main(int argc, char** argv) try {
  if (argc < 2) return std::fprintf(stderr, "usage: consumer PUBLISH_ENDPOINT [LAST]\n"), 2;
  zmq::context_t context;
  zmq::socket_t sub(context, zmq::socket_type::sub);
  sub.set(zmq::sockopt::subscribe, "cam");
  sub.set(zmq::sockopt::rcvtimeo, 10000);
  fq::client::PeerMonitor monitor(sub, "consumer");
  sub.connect(argv[1]);
  monitor.wait_for_peer(5000);  // results published before fqd has the subscription are lost
  std::fprintf(stderr, "waiting for results on %s\n", argv[1]);
  for (fq::client::ReceivedResult r;;) {
    const fq::StatusOr<bool> got = fq::client::receive_result(sub, r);
    if (got.ok() && !*got) throw std::runtime_error("no result within 10 s");
    if (got.ok() && r.topic != "cam") continue;  // topics are prefixes: "cam1" too
    fq::Status s = got.ok() ? fq::client::decode_result(r) : got.status();
    if (!s.ok() || !(s = fq::client::check_result(r)).ok()) throw std::runtime_error(s.message());
    double worst = 0, squares = 0, n = r.mesh.num_vertices();
    for (size_t i = 0; i < r.mesh.positions.size(); i += 3) {
      const float* p = &r.mesh.positions[i];
      const double off = std::hypot(std::hypot(p[0], p[1]) - 3, p[2]) - 1;  // off the tube's surface
      worst = std::fmax(worst, std::abs(off)), squares += off * off;
    }
    std::printf("result %lu: %s, %.0f vertices, %.1f ms, off the torus rms %.4f max %.4f\n",
                r.header.sequence(), fq::wire::ResultStatus_Name(r.header.status()).c_str(), n,
                r.header.latency_ms(), std::sqrt(squares / n), worst);
    if (r.header.sequence() == (argc > 2 ? std::stoull(argv[2]) : 4)) return 0;
  }
} catch (const std::exception& e) {  // also a bad endpoint (zmq::error_t) or number
  return std::fprintf(stderr, "consumer: %s\n", e.what()), 1;
}
