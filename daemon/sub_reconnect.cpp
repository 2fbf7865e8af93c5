#include "daemon/sub_reconnect.h"

#include <atomic>
#include <cstring>

namespace fq::daemon {
namespace {

// libzmq announces its own retry at once; a second leaves room for a busy I/O thread.
constexpr std::chrono::seconds kRetryAnnounced{1};

std::string monitor_address() {
  static std::atomic<int> next{0};
  return "inproc://fq-ingest-sub-monitor-" + std::to_string(next++);
}

}  // namespace

SubReconnector::SubReconnector(zmq::context_t& ctx, zmq::socket_t& sub) : monitor_(ctx, zmq::socket_type::pair) {
  const std::string address = monitor_address();
  if (zmq_socket_monitor(sub.handle(), address.c_str(),
                         ZMQ_EVENT_DISCONNECTED | ZMQ_EVENT_CONNECT_RETRIED | ZMQ_EVENT_CONNECTED) != 0)
    throw zmq::error_t();
  monitor_.set(zmq::sockopt::linger, 0);
  monitor_.connect(address);
}

void SubReconnector::check(zmq::socket_t& sub) {
  zmq::message_t event, endpoint;
  while (monitor_.recv(event, zmq::recv_flags::dontwait)) {
    if (!event.more() || !monitor_.recv(endpoint, zmq::recv_flags::none) || event.size() < 2) continue;
    uint16_t id = 0;
    std::memcpy(&id, event.data<char>(), 2);
    if (id == ZMQ_EVENT_DISCONNECTED)
      dropped_[endpoint.to_string()] = std::chrono::steady_clock::now();
    else
      dropped_.erase(endpoint.to_string());  // libzmq is on it
  }
  const auto now = std::chrono::steady_clock::now();
  for (auto it = dropped_.begin(); it != dropped_.end();) {
    if (now - it->second < kRetryAnnounced) {
      ++it;
      continue;
    }
    log_.log(spdlog::level::warn,
             "ingest: the connection to {} was dropped for a protocol error (a part over caps.max_frame_bytes, "
             "or a failed CURVE handshake); connecting again",
             it->first);
    try {
      sub.disconnect(it->first);
    } catch (const zmq::error_t&) {  // libzmq forgot the endpoint already
    }
    sub.connect(it->first);
    it = dropped_.erase(it);
  }
}

}  // namespace fq::daemon
