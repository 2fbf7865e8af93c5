// The publisher thread: owns the publish socket (an XPUB, result_socket.h), stamps each result's publish time
// and latency, publishes [stream id][ResultHeader][chunks...] and keeps each stream's results in arrival
// order (ticketed frames can finish out of order on several engines; a stream's order is its Stream's,
// stream.h).
#pragma once

#include <cstdint>
#include <set>
#include <string>
#include <zmq.hpp>

#include "daemon/pipeline/pipeline.h"
#include "daemon/pipeline/result_socket.h"

namespace fq::daemon {

class Publisher {
 public:
  Publisher(ResultSocket socket, Pipeline& p) : socket_(std::move(socket)), p_(p) {}

  /// Publishes until the publish queue is closed and drained, then closes the socket.
  void run();

 private:
  void accept(FramePtr f);
  void publish(FrameJob& f);
  void account(const FrameJob& f, const wire::ResultHeader& h);

  ResultSocket socket_;
  Pipeline& p_;
  /// The streams holding results back for an earlier ticket; each held frame keeps its stream.
  std::set<Stream*> holding_;
};

/// The ResultHeader of `f` as published at `publish_ns`.
wire::ResultHeader make_result_header(const FrameJob& f, int64_t publish_ns);

}  // namespace fq::daemon
