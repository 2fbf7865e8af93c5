// The control socket (REP): get/set a stream's parameters at run time, list streams,
// read counters and latency percentiles. Requests and replies are protobuf messages
// (ControlRequest / ControlReply in wire/fq.proto); a bad request gets ok = false.
#pragma once

#include <string_view>
#include <zmq.hpp>

#include "daemon/config/live_caps.h"
#include "daemon/pipeline/curve_auth.h"
#include "daemon/stream/stream_registry.h"
#include "wire/fq.pb.h"

namespace fq::daemon {

/// The largest control request (ZMQ_MAXMSGSIZE of the control socket: a larger part drops the
/// connection before it is buffered). A request is a few hundred bytes: a stream id (at most
/// caps.max_stream_id_bytes) and parameters.
inline constexpr size_t kMaxControlBytes = 64 << 10;

/// Answers one request under `caps`. A SetParams change is for a stream id the ingest would
/// admit (check_stream_id) and, without its `create`, one the registry knows (else refused,
/// naming the nearest known ids); it is validated with fq::validate and takes effect on the
/// stream's next frame to be decoded.
wire::ControlReply handle_control(const wire::ControlRequest& request, StreamRegistry& registry,
                                  const Caps& caps);

/// Parses, answers and serializes one request (an unparsable one gets an error reply).
std::string handle_control_bytes(std::string_view request, StreamRegistry& registry, const Caps& caps);

/// Serves requests until the socket's context is shut down, then closes the socket. A request
/// of more than one part is refused as a whole (one error reply, counted `oversized`); one
/// from a client key revoked since it connected gets an error and its connection cut.
void run_control(zmq::socket_t socket, StreamRegistry& registry, const LiveCaps& caps,
                 const ClientKeys* keys = nullptr);

}  // namespace fq::daemon
