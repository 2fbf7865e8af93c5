#include "daemon/sub_ingest.h"

#include <spdlog/spdlog.h>

#include <zmq_addon.hpp>

#include "daemon/curve_auth.h"
#include "daemon/ingest.h"

namespace fq::daemon {

Status make_sub_socket(zmq::context_t& ctx, const SubIngestConfig& config, uint64_t max_frame_bytes,
                       const CurveKeyPair* curve_server, zmq::socket_t& out,
                       std::unique_ptr<SubReconnector>& reconnector) {
  out = zmq::socket_t(ctx, zmq::socket_type::sub);
  reconnector = std::make_unique<SubReconnector>(ctx, out);
  out.set(zmq::sockopt::linger, 0);
  out.set(zmq::sockopt::maxmsgsize, static_cast<int64_t>(max_frame_bytes));
  out.set(zmq::sockopt::rcvhwm, kIngestMark);  // what libzmq holds while the decode queue is full
  // The mechanism's roles do not follow bind and connect: fqd is the CURVE server here too, so
  // producers use the same keys (--server-key fqd.pub --key-file cam.key) for PUSH and PUB.
  if (curve_server) make_curve_server(out, *curve_server);
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

void run_sub_ingest(zmq::socket_t pull, zmq::socket_t sub, SubReconnector& reconnector, Pipeline& p,
                    const std::set<std::string>& streams) {
  LogLimiter errors;
  zmq::pollitem_t items[] = {{pull.handle(), 0, ZMQ_POLLIN, 0}, {sub.handle(), 0, ZMQ_POLLIN, 0}};
  for (;;) {
    const CpuScope cpu(p.stage_cpu[CpuStage::kIngest]);
    try {
      expire_idle_streams(p);
      reconnector.check(sub);
      zmq::poll(items, 2, std::chrono::milliseconds(1000));  // wakes for the idle sweep
      if (items[0].revents & ZMQ_POLLIN) ingest_one(pull, p, zmq::recv_flags::dontwait);
      if (items[1].revents & ZMQ_POLLIN) ingest_one(sub, p, zmq::recv_flags::dontwait, &streams);
    } catch (const zmq::error_t& e) {
      if (e.num() == ETERM) break;
      errors.log(spdlog::level::err, "ingest: {}", e.what());
    }
  }
  reconnector.close();
  pull.close();
  sub.close();
}

}  // namespace fq::daemon
