// One multipart message from a ZeroMQ socket, with bounds on its parts and its bytes.
// ZMQ_MAXMSGSIZE bounds one part, not a message, and zmq::recv_multipart keeps every part (a
// control request of 100,000 parts was answered part by part: 100,000 error lines). Here the
// parts past a bound are dropped as they are read, the message is refused once (the caller
// answers or counts it), and the socket stays in step (the whole message is consumed, so a REP
// socket can still answer it). libzmq itself delivers a message only when all its parts have
// arrived and holds them until they are read; it has no bound on the number of parts
// (docs/RELIABILITY.md, "Limits").
#pragma once

#include <cstdint>
#include <vector>
#include <zmq.hpp>

namespace fq::daemon {

struct MessageBounds {
  size_t max_parts;
  uint64_t max_bytes;  ///< all parts together
};

enum class Received {
  kNothing,       ///< no message (a receive timeout, or EAGAIN without wait)
  kMessage,       ///< `parts` holds the whole message
  kTooManyParts,  ///< over max_parts: `parts` keeps the first part only, the rest was dropped
  kTooManyBytes,  ///< over max_bytes: likewise
};

/// Receives one message into `parts` (cleared first). Throws zmq::error_t as recv does.
Received receive_bounded(zmq::socket_t& socket, std::vector<zmq::message_t>& parts,
                         const MessageBounds& bounds, zmq::recv_flags flags = zmq::recv_flags::none);

}  // namespace fq::daemon
