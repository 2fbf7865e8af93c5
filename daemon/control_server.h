// The control socket (REP): get/set a stream's parameters at run time, list streams,
// read counters and latency percentiles. Requests and replies are protobuf messages
// (ControlRequest / ControlReply in wire/fq.proto); a bad request gets ok = false.
#pragma once

#include <string_view>
#include <zmq.hpp>

#include "wire/fq.pb.h"
#include "daemon/stream_registry.h"

namespace fq::daemon {

/// Answers one request. A SetParams change is validated with fq::validate and takes
/// effect on the stream's next frame to be decoded.
wire::ControlReply handle_control(const wire::ControlRequest& request, StreamRegistry& registry);

/// Parses, answers and serializes one request (an unparsable one gets an error reply).
std::string handle_control_bytes(std::string_view request, StreamRegistry& registry);

/// Serves requests until the socket's context is shut down, then closes the socket.
void run_control(zmq::socket_t socket, StreamRegistry& registry);

}  // namespace fq::daemon
