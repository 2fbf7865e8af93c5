// The ingest thread: owns the PULL socket, checks each message's framing and header
// (cheap checks only, so it always keeps up) and hands frames to the decode pool.
#pragma once

#include <zmq.hpp>

#include "daemon/pipeline.h"

namespace fq::daemon {

/// Receives until the socket's context is shut down, then closes the socket.
void run_ingest(zmq::socket_t socket, Pipeline& p);

/// Builds the job for one ingest message: on success the frame for the decode pool,
/// otherwise a job whose `error` is set (its stream id is the message's topic).
FramePtr admit_message(std::vector<zmq::message_t>& parts, Pipeline& p);

/// Hands an admitted job on: refusals and errors to the publisher, frames to the decoders.
void queue_admitted(FramePtr f, Pipeline& p);

/// At most once a second: forgets idle streams and frees idle pools (ingest thread).
void expire_idle_streams(Pipeline& p);

}  // namespace fq::daemon
