#include "daemon/pipeline/result_socket.h"

#include <algorithm>

namespace fq::daemon {

void ResultSocket::configure(zmq::socket_t& xpub, int max_results, uint32_t max_topic_bytes) {
  xpub.set(zmq::sockopt::sndhwm, max_results);
  xpub.set(zmq::sockopt::xpub_nodrop, 1);
  // Set, not autotuned (Linux grows it to 4 MiB by default): part of the documented bound.
  xpub.set(zmq::sockopt::sndbuf, kSendBufferBytes);
  // Subscriptions are topics, at most a stream id ([1|0] + id): a peer sending more is
  // disconnected before the bytes are buffered. The bound also applies to the handshake's
  // commands (CURVE's INITIATE is about 300 bytes), hence the floor.
  xpub.set(zmq::sockopt::maxmsgsize, std::max<int64_t>(int64_t{max_topic_bytes} + 1, kMinMessageBytes));
  // Subscriptions libzmq takes in from one subscriber before fqd counts them: what a
  // subscriber past the caps can add before it is cut (subscription_gate.h).
  xpub.set(zmq::sockopt::rcvhwm, kSubscriptionsInFlight);
}

bool ResultSocket::try_send(const std::vector<zmq::const_buffer>& parts) {
  for (size_t i = 0; i < parts.size(); ++i) {
    const zmq::send_flags more = i + 1 < parts.size() ? zmq::send_flags::sndmore : zmq::send_flags::none;
    if (!socket_.send(parts[i], more | zmq::send_flags::dontwait)) {
      // Only the first part can be refused: a message that started goes out whole.
      if (i > 0) throw zmq::error_t();
      return false;
    }
  }
  return true;
}

bool ResultSocket::send(const std::vector<zmq::const_buffer>& parts) {
  if (try_send(parts)) return true;
  socket_.set(zmq::sockopt::xpub_nodrop, 0);
  try_send(parts);  // never refused without NODROP: full queues skip it
  socket_.set(zmq::sockopt::xpub_nodrop, 1);
  return false;
}

}  // namespace fq::daemon
