#include "daemon/result_socket.h"

namespace fq::daemon {

void ResultSocket::configure(zmq::socket_t& xpub, int max_results) {
  xpub.set(zmq::sockopt::sndhwm, max_results);
  xpub.set(zmq::sockopt::xpub_nodrop, 1);
  // Set, not autotuned (Linux grows it to 4 MiB by default): part of the documented bound.
  xpub.set(zmq::sockopt::sndbuf, kSendBufferBytes);
  // Subscriptions are topics (stream ids of at most a few hundred bytes): a peer sending
  // more is disconnected before the bytes are buffered.
  xpub.set(zmq::sockopt::maxmsgsize, int64_t{64} << 10);
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

void ResultSocket::drain_subscriptions() {
  zmq::message_t m;
  while (socket_.recv(m, zmq::recv_flags::dontwait)) {
  }
}

}  // namespace fq::daemon
