#include "daemon/pipeline/sub_producers.h"

#include <cstring>

#include "daemon/pipeline/curve_auth.h"
#include "daemon/pipeline/ingest.h"

namespace fq::daemon {
namespace {

// libzmq announces its own retry at once; a second leaves room for a busy I/O thread.
constexpr std::chrono::seconds kRetryAnnounced{1};

std::string monitor_address() {
  static std::atomic<int> next{0};
  return "inproc://fq-ingest-sub-monitor-" + std::to_string(next++);
}

}  // namespace

SubProducers::SubProducers(zmq::context_t& ctx, SubSocketRules rules, std::atomic<uint64_t>& replaced)
    : ctx_(ctx), rules_(std::move(rules)), replaced_(replaced) {}

Status SubProducers::add(const std::string& endpoint) {
  producers_.push_back(Producer{endpoint, {}, {}, {}});
  try {
    open(producers_.back());
  } catch (const zmq::error_t& e) {
    producers_.pop_back();
    return invalid_argument("cannot connect the ingest SUB socket to " + endpoint + ": " + e.what());
  }
  return {};
}

void SubProducers::open(Producer& p) {
  zmq::socket_t sub(ctx_, zmq::socket_type::sub);
  sub.set(zmq::sockopt::linger, 0);
  sub.set(zmq::sockopt::maxmsgsize, static_cast<int64_t>(rules_.max_frame_bytes));
  sub.set(zmq::sockopt::rcvhwm, kIngestMark);  // what libzmq holds while the decode queue is full
  // The mechanism's roles do not follow bind and connect: fqd is the CURVE server here too, so
  // producers use the same keys (--server-key fqd.pub --key-file cam.key) for PUSH and PUB.
  if (rules_.curve_server) make_curve_server(sub, *rules_.curve_server);
  if (rules_.streams.empty()) sub.set(zmq::sockopt::subscribe, "");
  for (const std::string& s : rules_.streams) sub.set(zmq::sockopt::subscribe, s);
  const std::string address = monitor_address();
  if (zmq_socket_monitor(sub.handle(), address.c_str(),
                         ZMQ_EVENT_DISCONNECTED | ZMQ_EVENT_CONNECT_RETRIED | ZMQ_EVENT_CONNECTED) != 0)
    throw zmq::error_t();
  zmq::socket_t monitor(ctx_, zmq::socket_type::pair);
  monitor.set(zmq::sockopt::linger, 0);
  monitor.connect(address);
  sub.connect(p.endpoint);
  // The old socket (if any) closes here, with its connection that libzmq gave up on.
  p.monitor = std::move(monitor);
  p.sub = std::move(sub);
  p.dropped.reset();
}

void SubProducers::check() {
  const auto now = std::chrono::steady_clock::now();
  for (Producer& p : producers_) {
    zmq::message_t event, endpoint;
    while (p.monitor.recv(event, zmq::recv_flags::dontwait)) {
      if (!event.more() || !p.monitor.recv(endpoint, zmq::recv_flags::none) || event.size() < 2) continue;
      uint16_t id = 0;
      std::memcpy(&id, event.data<char>(), 2);
      if (id == ZMQ_EVENT_DISCONNECTED)
        p.dropped = now;
      else
        p.dropped.reset();  // libzmq is on it
    }
    if (!p.dropped || now - *p.dropped < kRetryAnnounced) continue;
    log_.log(
        spdlog::level::warn,
        "ingest: the connection to {} was dropped for a protocol error (a part over caps.max_frame_bytes, "
        "or a failed CURVE handshake); connecting again",
        p.endpoint);
    open(p);
    replaced_.fetch_add(1, std::memory_order_relaxed);
  }
}

void SubProducers::close() {
  for (Producer& p : producers_) {
    p.monitor.close();
    p.sub.close();
  }
}

}  // namespace fq::daemon
