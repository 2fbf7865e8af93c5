// A REQ client for fqd's control socket.
#pragma once

#include <string>
#include <zmq.hpp>

#include "common/status.h"
#include "wire/fq.pb.h"

namespace fq::client {

/// Sends one request and waits up to `timeout_ms` for the reply (REQ sockets cannot be
/// reused after a timeout: the caller makes a new one). Non-ok for a transport failure,
/// an unparsable reply or a reply with ok = false (its error message).
Status control_call(zmq::socket_t& req, const wire::ControlRequest& request, wire::ControlReply& reply,
                    int timeout_ms = 5000);

}  // namespace fq::client
