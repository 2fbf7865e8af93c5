#include "clients/common/peer_monitor.h"

#include <cerrno>
#include <chrono>

namespace fq::client {

PeerMonitor::PeerMonitor(zmq::socket_t& socket, const std::string& name) {
  init(socket, "inproc://fq-peer-monitor-" + name,
       ZMQ_EVENT_HANDSHAKE_SUCCEEDED | ZMQ_EVENT_DISCONNECTED | ZMQ_EVENT_HANDSHAKE_FAILED_AUTH);
}

void PeerMonitor::poll() {
  try {
    while (check_event(0)) {
    }
  } catch (const zmq::error_t& e) {
    if (e.num() != EINTR) throw;  // a signal: the events wait for the next call
  }
}

bool PeerMonitor::wait_for_peer(int ms) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(ms);
  poll();
  while (peers_ == 0 && !refused()) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) break;
    try {
      check_event(int(left.count()));
    } catch (const zmq::error_t& e) {
      if (e.num() != EINTR) throw;
      break;
    }
  }
  return peers_ > 0;
}

void PeerMonitor::on_event_handshake_succeeded(const zmq_event_t&, const char*) {
  ++peers_;
  ever_ = true;
}

void PeerMonitor::on_event_disconnected(const zmq_event_t&, const char*) {
  if (peers_ > 0) --peers_;
}

void PeerMonitor::on_event_handshake_failed_auth(const zmq_event_t& event, const char* address) {
  refused_status_ = event.value > 0 ? int(event.value) : 400;
  refused_by_ = address ? address : "";
}

}  // namespace fq::client
