#include "daemon/pipeline/bounded_receive.h"

namespace fq::daemon {

Received receive_bounded(zmq::socket_t& socket, std::vector<zmq::message_t>& parts,
                         const MessageBounds& bounds, zmq::recv_flags flags) {
  parts.clear();
  zmq::message_t part;
  if (!socket.recv(part, flags)) return Received::kNothing;
  Received result = Received::kMessage;
  uint64_t bytes = part.size();
  bool more = part.more();
  parts.push_back(std::move(part));
  if (bytes > bounds.max_bytes) result = Received::kTooManyBytes;
  // The rest of a message is already here (ZeroMQ delivers messages whole): no waiting.
  while (more) {
    zmq::message_t next;
    (void)socket.recv(next, zmq::recv_flags::none);
    more = next.more();
    if (result != Received::kMessage) continue;  // dropped as it comes
    bytes += next.size();
    if (parts.size() + 1 > bounds.max_parts)
      result = Received::kTooManyParts;
    else if (bytes > bounds.max_bytes)
      result = Received::kTooManyBytes;
    else
      parts.push_back(std::move(next));
  }
  if (result != Received::kMessage) parts.resize(1);
  return result;
}

}  // namespace fq::daemon
