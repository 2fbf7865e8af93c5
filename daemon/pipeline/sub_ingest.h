// Ingest by subscription, for scale-out: besides its PULL socket, fqd SUB-connects to the PUB
// endpoints of producers ([ingest] connect) and takes only the stream ids assigned to it
// ([ingest] streams), so that several fqd processes can share the streams of the same
// producers (topic sharding) and each stream is served by exactly one of them.
#pragma once

#include <atomic>
#include <memory>
#include <string>
#include <zmq.hpp>

#include "common/curve_keys.h"
#include "daemon/config/service_config.h"
#include "daemon/pipeline/sub_producers.h"

namespace fq::daemon {

/// Makes the SUB sockets, one per endpoint (sub_producers.h), each subscribed to every
/// assigned stream (all streams when `streams` is empty), under the rules of the PULL socket: a
/// part over `max_frame_bytes` drops the connection, and with `curve_server` (fqd's keys,
/// [security]) every producer must authenticate with an allowed client key (ZAP, as on the
/// PULL socket; the producer's PUB is the CURVE client). `reconnects` counts the producers
/// connected again after libzmq gave them up. kInvalidArgument for an endpoint ZeroMQ refuses.
Status make_sub_producers(zmq::context_t& ctx, const SubIngestConfig& config, uint64_t max_frame_bytes,
                          const CurveKeyPair* curve_server, std::atomic<uint64_t>& reconnects,
                          std::unique_ptr<SubProducers>& out);

}  // namespace fq::daemon
