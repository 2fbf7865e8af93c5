#include "daemon/sub_ingest.h"

#include <spdlog/spdlog.h>

#include <zmq_addon.hpp>

#include "daemon/ingest.h"

namespace fq::daemon {

Status make_sub_socket(zmq::context_t& ctx, const SubIngestConfig& config, zmq::socket_t& out) {
  out = zmq::socket_t(ctx, zmq::socket_type::sub);
  out.set(zmq::sockopt::linger, 0);
  // Frames are large and a late one is superseded anyway: keep the default queue bound.
  if (config.streams.empty()) out.set(zmq::sockopt::subscribe, "");
  for (const std::string& s : config.streams) out.set(zmq::sockopt::subscribe, s);
  for (const std::string& ep : config.connect) {
    try {
      out.connect(ep);
    } catch (const zmq::error_t& e) {
      return invalid_argument("cannot connect the ingest SUB socket to " + ep + ": " + e.what());
    }
  }
  return {};
}

namespace {

// One whole message from `s` (which poll said is readable) into `parts`.
bool receive(zmq::socket_t& s, std::vector<zmq::message_t>& parts) {
  parts.clear();
  return zmq::recv_multipart(s, std::back_inserter(parts), zmq::recv_flags::dontwait).has_value();
}

}  // namespace

void run_sub_ingest(zmq::socket_t pull, zmq::socket_t sub, Pipeline& p, const std::set<std::string>& streams) {
  std::vector<zmq::message_t> parts;
  zmq::pollitem_t items[] = {{pull.handle(), 0, ZMQ_POLLIN, 0}, {sub.handle(), 0, ZMQ_POLLIN, 0}};
  for (;;) {
    const CpuScope cpu(p.stage_cpu[CpuStage::kIngest]);
    try {
      expire_idle_streams(p);
      zmq::poll(items, 2, std::chrono::milliseconds(1000));  // wakes for the idle sweep
      if ((items[0].revents & ZMQ_POLLIN) && receive(pull, parts)) queue_admitted(admit_message(parts, p), p);
      if ((items[1].revents & ZMQ_POLLIN) && receive(sub, parts)) {
        if (streams.empty() || (!parts.empty() && streams.count(parts[0].to_string())))
          queue_admitted(admit_message(parts, p), p);
      }
    } catch (const zmq::error_t& e) {
      if (e.num() == ETERM) break;
      spdlog::error("ingest: {}", e.what());
    }
  }
  pull.close();
  sub.close();
}

}  // namespace fq::daemon
