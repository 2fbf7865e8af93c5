#include "daemon/control_server.h"

#include <spdlog/spdlog.h>

#include "daemon/settings_audit.h"
#include "proto/header_codec.h"

namespace fq::daemon {
namespace {

wire::ControlReply ok_reply() {
  wire::ControlReply r;
  r.set_version(wire::kWireVersion);
  r.set_ok(true);
  return r;
}

wire::ControlReply error_reply(const std::string& message) {
  wire::ControlReply r = ok_reply();
  r.set_ok(false);
  r.set_error(message);
  return r;
}

/// The reply to get_params and set_params: the stream's parameters, compute and result form.
wire::ControlReply settings_reply(const StreamSettings& s) {
  wire::ControlReply r = ok_reply();
  wire::params_to_wire(s.params, *r.mutable_params());
  r.set_compute(wire::compute_of(s.params));
  r.set_result_form(to_wire(s.output.form));
  return r;
}

wire::ControlReply get_params(const wire::GetParams& q, StreamRegistry& registry) {
  StreamSettings s;
  if (!registry.find(q.stream_id(), s)) return error_reply("unknown stream '" + q.stream_id() + "'");
  return settings_reply(s);
}

wire::ControlReply set_params(const wire::SetParams& q, StreamRegistry& registry) {
  if (q.stream_id().empty()) return error_reply("set_params needs a stream id");
  StreamSettings s;
  if (!registry.settings(q.stream_id(), s)) return error_reply("too many streams");
  const StreamSettings before = s;
  Status st = wire::apply_overrides(q.params(), s.params);
  if (st.ok() && q.has_compute()) st = wire::apply_compute(q.compute(), s.params);
  if (st.ok()) st = validate(s);
  if (!st.ok()) return error_reply("invalid parameters: " + st.message());
  if (q.has_result_form()) s.output.form = from_wire(q.result_form());
  registry.set_settings(q.stream_id(), s);
  log_settings_changes(q.stream_id(), before, s, "control");
  return settings_reply(s);
}

wire::ControlReply get_counters(const wire::GetCounters& q, StreamRegistry& registry) {
  std::vector<StreamSnapshot> snaps;
  if (!registry.snapshot(q.stream_id(), snaps)) return error_reply("unknown stream '" + q.stream_id() + "'");
  wire::ControlReply r = ok_reply();
  for (const StreamSnapshot& s : snaps) {
    wire::StreamCounters* c = r.add_counters();
    c->set_stream_id(s.stream_id);
    c->set_frames_in(s.counters.frames_in);
    c->set_frames_out(s.counters.frames_out);
    c->set_superseded(s.counters.superseded);
    c->set_dropped_stale(s.counters.dropped_stale);
    c->set_late(s.counters.late);
    c->set_errors(s.counters.errors);
    c->set_time_limited(s.counters.time_limited);
    c->set_temporal_resets(s.counters.temporal_resets);
    c->set_subscriber_overflows(s.counters.subscriber_overflows);
    for (const auto& [name, pc] : s.stages) {
      wire::StagePercentiles* sp = c->add_stages();
      sp->set_name(name);
      sp->set_p50_ms(pc.p50_ms);
      sp->set_p95_ms(pc.p95_ms);
      sp->set_p99_ms(pc.p99_ms);
      sp->set_count(pc.count);
    }
  }
  return r;
}

}  // namespace

wire::ControlReply handle_control(const wire::ControlRequest& request, StreamRegistry& registry) {
  switch (request.request_case()) {
    case wire::ControlRequest::kGetParams:
      return get_params(request.get_params(), registry);
    case wire::ControlRequest::kSetParams:
      return set_params(request.set_params(), registry);
    case wire::ControlRequest::kListStreams: {
      wire::ControlReply r = ok_reply();
      for (const std::string& id : registry.list()) r.add_streams(id);
      return r;
    }
    case wire::ControlRequest::kGetCounters:
      return get_counters(request.get_counters(), registry);
    case wire::ControlRequest::REQUEST_NOT_SET:
      break;
  }
  return error_reply("empty control request");
}

std::string handle_control_bytes(std::string_view bytes, StreamRegistry& registry) {
  wire::ControlRequest request;
  if (Status s = wire::parse_control_request(bytes, request); !s.ok())
    return error_reply(s.message()).SerializeAsString();
  return handle_control(request, registry).SerializeAsString();
}

void run_control(zmq::socket_t socket, StreamRegistry& registry) {
  for (;;) {
    zmq::message_t request;
    try {
      if (!socket.recv(request)) continue;
      const std::string reply =
          handle_control_bytes(std::string_view(request.data<char>(), request.size()), registry);
      socket.send(zmq::buffer(reply), zmq::send_flags::none);
    } catch (const zmq::error_t& e) {
      if (e.num() == ETERM) break;
      spdlog::error("control: {}", e.what());
    }
  }
  socket.close();
}

}  // namespace fq::daemon
