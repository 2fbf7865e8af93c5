#include "daemon/pipeline/subscription_gate.h"

#include <sys/socket.h>

#include <atomic>
#include <cstring>

namespace fq::daemon {
namespace {

std::string monitor_address() {
  static std::atomic<int> next{0};
  return "inproc://fq-publish-monitor-" + std::to_string(next++);
}

}  // namespace

zmq::socket_t SubscriptionGate::monitor(zmq::context_t& ctx, zmq::socket_t& xpub) {
  xpub.set(zmq::sockopt::xpub_verboser, 1);
  const std::string address = monitor_address();
  if (zmq_socket_monitor(xpub.handle(), address.c_str(), ZMQ_EVENT_ACCEPTED | ZMQ_EVENT_DISCONNECTED) != 0)
    throw zmq::error_t();
  zmq::socket_t pair(ctx, zmq::socket_type::pair);
  pair.set(zmq::sockopt::linger, 0);
  pair.connect(address);
  return pair;
}

void SubscriptionGate::connection_events() {
  zmq::message_t event, address;
  while (monitor_.recv(event, zmq::recv_flags::dontwait)) {
    if (event.more()) (void)monitor_.recv(address, zmq::recv_flags::none);
    if (event.size() < 6) continue;
    uint16_t id = 0;
    uint32_t fd = 0;
    std::memcpy(&id, event.data<char>(), 2);
    std::memcpy(&fd, event.data<char>() + 2, 4);
    // A new peer starts from nothing, also on the number of one that left.
    if (id == ZMQ_EVENT_ACCEPTED) peers_[static_cast<int>(fd)] = {};
    if (id == ZMQ_EVENT_DISCONNECTED) peers_.erase(static_cast<int>(fd));
  }
}

void SubscriptionGate::subscription(const zmq::message_t& m) {
  if (m.size() == 0 || (m.data<uint8_t>()[0] != 0 && m.data<uint8_t>()[0] != 1)) return;
  const bool subscribe = m.data<uint8_t>()[0] == 1;
  const std::string_view topic(m.data<char>() + 1, m.size() - 1);
  // A departed subscriber's unsubscriptions come without a socket: libzmq dropped it already.
  auto* msg = const_cast<zmq_msg_t*>(m.handle());
  const int fd = zmq_msg_get(msg, ZMQ_SRCFD);
  if (fd < 0) return;
  Peer& peer = peers_[fd];
  if (peer.cut) return;
  if (keys_) {
    peer.key = sender_key(m);
    if (!keys_->allowed(peer.key)) {  // revoked since it connected
      refusals_->add(Refusal::kUnauthenticated);
      return cut(fd, peer);
    }
  }
  const auto known = peer.topics.find(topic);
  if (!subscribe) {
    if (known == peer.topics.end()) return;
    peer.bytes -= known->size();
    peer.topics.erase(known);
    return;
  }
  if (known != peer.topics.end()) return;  // libzmq keeps one
  if (peer.topics.size() + 1 <= caps_.max_count && peer.bytes + topic.size() <= caps_.max_bytes) {
    peer.topics.emplace(topic);
    peer.bytes += topic.size();
    return;
  }
  refusals_->add(Refusal::kSubscriptions);
  const char* address = zmq_msg_gets(msg, "Peer-Address");
  log_->log(spdlog::level::warn,
            "publish: cut a subscriber from {}: over caps.max_subscriptions = {} subscriptions or "
            "caps.max_subscription_bytes = {} bytes of topics",
            address ? address : "?", caps_.max_count, caps_.max_bytes);
  cut(fd, peer);
}

void SubscriptionGate::cut(int fd, Peer& peer) {
  // Shut down, not closed: the socket stays libzmq's, which sees the end and drops the peer
  // with everything it subscribed.
  ::shutdown(fd, SHUT_RDWR);
  peer = Peer{};
  peer.cut = true;
}

void SubscriptionGate::revoke() {
  keys_seen_ = keys_->generation();
  for (auto& [fd, peer] : peers_) {
    if (peer.cut || peer.key.empty() || keys_->allowed(peer.key)) continue;
    refusals_->add(Refusal::kUnauthenticated);
    log_->log(spdlog::level::warn, "publish: cut a subscriber whose client key {} was revoked", peer.key);
    cut(fd, peer);
  }
}

void SubscriptionGate::drain(zmq::socket_t& xpub) {
  connection_events();  // first: a departed peer's number may be a new peer's now
  if (keys_ && keys_->generation() != keys_seen_) revoke();
  zmq::message_t m;
  while (xpub.recv(m, zmq::recv_flags::dontwait)) subscription(m);
}

}  // namespace fq::daemon
