#include "daemon/pipeline/sub_ingest.h"

#include <spdlog/spdlog.h>

#include <vector>
#include <zmq_addon.hpp>

#include "daemon/pipeline/ingest.h"

namespace fq::daemon {

Status make_sub_producers(zmq::context_t& ctx, const SubIngestConfig& config, uint64_t max_frame_bytes,
                          const CurveKeyPair* curve_server, std::atomic<uint64_t>& reconnects,
                          std::unique_ptr<SubProducers>& out) {
  SubSocketRules rules{config.streams, max_frame_bytes, {}};
  if (curve_server) rules.curve_server = *curve_server;
  out = std::make_unique<SubProducers>(ctx, std::move(rules), reconnects);
  for (const std::string& ep : config.connect) FQ_RETURN_IF_ERROR(out->add(ep));
  return {};
}

// The ingest thread with [ingest] connect (Ingest::run_with_producers, declared in ingest.h).
void Ingest::run_with_producers() {
  std::vector<zmq::pollitem_t> items;
  for (;;) {
    const CpuScope cpu(p_.stage_cpu[CpuStage::kIngest]);
    try {
      expire_idle_streams();
      producers_->check();
      items.assign(1, {pull_.handle(), 0, ZMQ_POLLIN, 0});
      for (size_t i = 0; i < producers_->size(); ++i)
        items.push_back({producers_->socket(i).handle(), 0, ZMQ_POLLIN, 0});
      zmq::poll(items, std::chrono::milliseconds(1000));  // wakes for the idle sweep and check()
      if (items[0].revents & ZMQ_POLLIN) ingest_one(pull_, zmq::recv_flags::dontwait);
      for (size_t i = 0; i < producers_->size(); ++i)
        if (items[i + 1].revents & ZMQ_POLLIN)
          ingest_one(producers_->socket(i), zmq::recv_flags::dontwait, &assigned_);
    } catch (const zmq::error_t& e) {
      if (e.num() == ETERM) break;
      errors_.log(spdlog::level::err, "ingest: {}", e.what());
    }
  }
  producers_->close();
  pull_.close();
}

}  // namespace fq::daemon
