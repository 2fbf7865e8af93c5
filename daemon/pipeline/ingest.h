// The ingest thread: owns the PULL socket, checks each message's framing and header
// (cheap checks only, so it always keeps up) and hands frames to the decode pool.
#pragma once

#include <set>
#include <string>
#include <zmq.hpp>

#include "daemon/pipeline/pipeline.h"

namespace fq::daemon {

/// The receive mark of the ingest sockets, in messages per producer connection: what libzmq
/// holds while fqd's decode queue is full and the ingest thread waits (then producers wait).
inline constexpr int kIngestMark = 4;

/// Receives until the socket's context is shut down, then closes the socket.
void run_ingest(zmq::socket_t socket, Pipeline& p);

/// Receives one message from `socket` (`flags`: dontwait when a poll said it is there) within
/// the ingest bounds (2 + wire::kMaxChunks parts, caps.max_frame_bytes in all, parts past them
/// dropped as read) and hands it on: admitted, or refused (`oversized`) when over them.
/// `assigned`: a SUB socket's stream ids, other topics are ignored (empty or null: all). False
/// when there was no message.
bool ingest_one(zmq::socket_t& socket, Pipeline& p, zmq::recv_flags flags,
                const std::set<std::string>* assigned = nullptr);

/// Builds the job for one ingest message: on success the frame for the decode pool,
/// otherwise a job whose `error` is set (its stream id is the message's topic).
FramePtr admit_message(std::vector<zmq::message_t>& parts, Pipeline& p);

/// Hands an admitted job on: refusals and errors to the publisher, frames to the decoders.
void queue_admitted(FramePtr f, Pipeline& p);

/// At most once a second: forgets idle streams and frees idle pools (ingest thread).
void expire_idle_streams(Pipeline& p);

}  // namespace fq::daemon
