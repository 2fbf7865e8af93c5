#include "daemon/control/control_server.h"

#include <spdlog/spdlog.h>

#include "common/nearest_names.h"
#include "daemon/config/stream_setting_table.h"
#include "daemon/control/settings_audit.h"
#include "daemon/pipeline/bounded_receive.h"
#include "daemon/pipeline/log_limiter.h"
#include "wire/header_codec.h"

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

/// The reply to get_params and set_params: the stream's parameters, compute mode and the
/// settings of the stream setting table.
wire::ControlReply settings_reply(const StreamSettings& s) {
  wire::ControlReply r = ok_reply();
  wire::params_to_wire(s.params, *r.mutable_params());
  r.set_compute(wire::compute_of(s.params));
  settings_to_wire(s, r);
  return r;
}

wire::ControlReply unknown_stream(const std::string& id) {
  return error_reply("unknown stream '" + printable_id(id) + "'");
}

// A set_params for a stream fqd does not know, without `create`: most likely a typo, which
// would otherwise make a stream that no producer feeds.
wire::ControlReply not_created(const std::string& id, const StreamRegistry& registry) {
  return error_reply("unknown stream '" + printable_id(id) + "'" + did_you_mean(id, registry.list()) +
                     "; to make it, set with create (fqctl set --create)");
}

// Parameter changes are logged (one line each, at most 5 a second: any control client can send them).
LogLimiter& change_log() {
  static LogLimiter log;
  return log;
}

wire::ControlReply get_params(const wire::GetParams& q, StreamRegistry& registry) {
  StreamSettings s;
  if (!registry.find(q.stream_id(), s)) return unknown_stream(q.stream_id());
  return settings_reply(s);
}

wire::ControlReply set_params(const wire::SetParams& q, StreamRegistry& registry, const Caps& caps) {
  if (q.stream_id().empty()) return error_reply("set_params needs a stream id");
  // The ingest's own check: control makes no stream that a frame could not make.
  Refusal why = Refusal::kBadStreamId;
  if (Status id = check_stream_id(q.stream_id(), caps, &why); !id.ok()) {
    registry.refusals().add(why);
    return error_reply(id.message());
  }
  StreamSettings s;
  if (!q.create() && !registry.find(q.stream_id(), s)) return not_created(q.stream_id(), registry);
  if (!registry.settings(q.stream_id(), s)) return error_reply("too many streams");
  const StreamSettings before = s;
  Status st = wire::apply_overrides(q.params(), s.params);
  if (st.ok() && q.has_compute()) st = wire::apply_compute(q.compute(), s.params);
  settings_from_wire(q, s);  // validate(s) below checks them
  if (st.ok()) st = validate(s);
  if (!st.ok()) return error_reply("invalid parameters: " + st.message());
  registry.set_settings(q.stream_id(), s);
  log_settings_changes(q.stream_id(), before, s, "control", &change_log());
  return settings_reply(s);
}

wire::ControlReply get_counters(const wire::GetCounters& q, StreamRegistry& registry) {
  std::vector<StreamSnapshot> snaps;
  if (!registry.snapshot(q.stream_id(), snaps)) return unknown_stream(q.stream_id());
  wire::ControlReply r = ok_reply();
  for (const StreamSnapshot& s : snaps) {
    wire::StreamCounters* c = r.add_counters();
    c->set_stream_id(s.stream_id);
#define FQ_COUNTER_TO_WIRE(name, metric, help) c->set_##name(s.counters.name);
    FQ_STREAM_COUNTERS(FQ_COUNTER_TO_WIRE)
#undef FQ_COUNTER_TO_WIRE
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

wire::ControlReply handle_control(const wire::ControlRequest& request, StreamRegistry& registry,
                                  const Caps& caps) {
  switch (request.request_case()) {
    case wire::ControlRequest::kGetParams:
      return get_params(request.get_params(), registry);
    case wire::ControlRequest::kSetParams:
      return set_params(request.set_params(), registry, caps);
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

std::string handle_control_bytes(std::string_view bytes, StreamRegistry& registry, const Caps& caps) {
  wire::ControlRequest request;
  if (Status s = wire::parse_control_request(bytes, request); !s.ok())
    return error_reply(s.message()).SerializeAsString();
  return handle_control(request, registry, caps).SerializeAsString();
}

void run_control(zmq::socket_t socket, StreamRegistry& registry, const LiveCaps& caps,
                 const ClientKeys* keys) {
  LogLimiter refused_log, error_log;
  std::vector<zmq::message_t> request;
  for (;;) {
    try {
      const Received got = receive_bounded(socket, request, {1, kMaxControlBytes});
      if (got == Received::kNothing) continue;
      std::string reply;
      if (!admit_sender(request[0], keys, registry.refusals())) {
        reply = error_reply("unauthenticated: this client key is no longer allowed").SerializeAsString();
      } else if (got == Received::kMessage) {
        reply = handle_control_bytes(std::string_view(request[0].data<char>(), request[0].size()), registry,
                                     *caps.get());
      } else {
        registry.refusals().add(Refusal::kOversized);
        refused_log.log(spdlog::level::warn, "control: refused a request of more than one part");
        reply = error_reply("a control request is one message part (ControlRequest)").SerializeAsString();
      }
      socket.send(zmq::buffer(reply), zmq::send_flags::none);
    } catch (const zmq::error_t& e) {
      if (e.num() == ETERM) break;
      error_log.log(spdlog::level::err, "control: {}", e.what());
    }
  }
  socket.close();
}

}  // namespace fq::daemon
