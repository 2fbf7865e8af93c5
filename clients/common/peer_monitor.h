// Whether a ZeroMQ socket has a peer (ZeroMQ's socket monitor: handshakes and disconnects).
// A PUSH socket queues and a PUB socket drops frames while no peer is there, both silently;
// fqpub uses this to say when no fqd is connected. Destroy it before closing the socket: its
// destructor stops the monitor on the socket.
#pragma once

#include <zmq.hpp>

#include <string>

namespace fq::client {

class PeerMonitor : public zmq::monitor_t {
 public:
  /// Watches `socket` (before it binds or connects, so that no event is missed).
  PeerMonitor(zmq::socket_t& socket, const std::string& name);

  /// Takes in the events that happened since the last call (does not wait).
  void poll();
  /// Waits up to `ms` for a peer (events, not sleeps); whether one is connected.
  bool wait_for_peer(int ms);
  /// Peers connected now (handshakes done minus disconnects), and whether one ever was.
  int peers() const { return peers_; }
  bool ever_connected() const { return ever_; }

 private:
  void on_event_handshake_succeeded(const zmq_event_t& event, const char* address) override;
  void on_event_disconnected(const zmq_event_t& event, const char* address) override;

  int peers_ = 0;
  bool ever_ = false;
};

}  // namespace fq::client
