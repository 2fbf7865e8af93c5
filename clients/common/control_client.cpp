#include "clients/common/control_client.h"

#include "wire/header_codec.h"

namespace fq::client {

Status control_call(zmq::socket_t& req, const wire::ControlRequest& request, wire::ControlReply& reply,
                    int timeout_ms) {
  req.set(zmq::sockopt::rcvtimeo, timeout_ms);
  wire::ControlRequest stamped = request;
  stamped.set_version(wire::kWireVersion);
  const std::string bytes = stamped.SerializeAsString();
  req.send(zmq::buffer(bytes), zmq::send_flags::none);
  zmq::message_t m;
  if (!req.recv(m))
    return {StatusCode::kUnavailable, "no control reply within " + std::to_string(timeout_ms) + " ms"};
  FQ_RETURN_IF_ERROR(wire::parse_control_reply(std::string_view(m.data<char>(), m.size()), reply));
  if (!reply.ok()) return invalid_argument(reply.error());
  return {};
}

}  // namespace fq::client
