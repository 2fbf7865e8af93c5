// Whether a ZeroMQ socket has a peer (ZeroMQ's socket monitor: handshakes and disconnects).
// A PUSH socket queues and a PUB socket drops frames while no peer is there, both silently;
// fqpub uses this to say when no fqd is connected. Destroy it before closing the socket: its
// destructor stops the monitor on the socket.
#pragma once

#include <string>
#include <zmq.hpp>

namespace fq::client {

class PeerMonitor : public zmq::monitor_t {
 public:
  /// Watches `socket` (before it binds or connects, so that no event is missed).
  PeerMonitor(zmq::socket_t& socket, const std::string& name);

  /// Takes in the events that happened since the last call (does not wait).
  void poll();
  /// Waits up to `ms` for a peer (events, not sleeps), or until one refuses our key; whether
  /// one is connected.
  bool wait_for_peer(int ms);
  /// Peers connected now (handshakes done minus disconnects), and whether one ever was.
  int peers() const { return peers_; }
  bool ever_connected() const { return ever_; }
  /// Whether a peer refused our CURVE key (ZMQ_EVENT_HANDSHAKE_FAILED_AUTH; ZeroMQ would retry
  /// for ever while frames wait), the ZAP status it gave (400: key not allowed) and where.
  bool refused() const { return refused_status_ != 0; }
  int refused_status() const { return refused_status_; }
  const std::string& refused_by() const { return refused_by_; }

 private:
  void on_event_handshake_succeeded(const zmq_event_t& event, const char* address) override;
  void on_event_disconnected(const zmq_event_t& event, const char* address) override;
  void on_event_handshake_failed_auth(const zmq_event_t& event, const char* address) override;

  int peers_ = 0;
  bool ever_ = false;
  int refused_status_ = 0;
  std::string refused_by_;
};

}  // namespace fq::client
