#include "daemon/result_socket.h"

#include <algorithm>

namespace fq::daemon {

void ResultSocket::configure(zmq::socket_t& xpub) {
  xpub.set(zmq::sockopt::sndhwm, kMaxHwm);
  xpub.set(zmq::sockopt::xpub_nodrop, 1);
  // Set, not autotuned (Linux grows it to 4 MiB by default): part of the documented bound.
  xpub.set(zmq::sockopt::sndbuf, kSendBufferBytes);
  // Subscriptions are topics (stream ids of at most a few hundred bytes): a peer sending
  // more is disconnected before the bytes are buffered.
  xpub.set(zmq::sockopt::maxmsgsize, int64_t{64} << 10);
}

void ResultSocket::fit_hwm(size_t message_bytes) {
  if (message_bytes <= largest_) return;
  largest_ = message_bytes;
  const uint64_t fit = std::max<uint64_t>(1, max_bytes_ / largest_);
  const int hwm = static_cast<int>(std::min<uint64_t>(fit, kMaxHwm));
  if (hwm == hwm_) return;
  hwm_ = hwm;
  socket_.set(zmq::sockopt::sndhwm, hwm_);
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
  size_t bytes = 0;
  for (const zmq::const_buffer& b : parts) bytes += b.size() + kPartOverhead;
  fit_hwm(bytes);
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
