// Keeps the ingest SUB socket connected to every producer. libzmq gives a connecting socket up
// for good when its peer breaks the protocol, and a part over ZMQ_MAXMSGSIZE (or a failed CURVE
// handshake) is such a break: fqd would stay away from that producer until a restart. A monitor
// of the SUB socket tells the cases apart: after an ordinary disconnect libzmq says at once
// that it retries (ZMQ_EVENT_CONNECT_RETRIED); when it has not said so within a second, fqd
// connects again itself (and so at most once a second per producer).
#pragma once

#include <chrono>
#include <map>
#include <string>
#include <zmq.hpp>

#include "daemon/log_limiter.h"

namespace fq::daemon {

class SubReconnector {
 public:
  /// Monitors `sub` (before it connects) through a PAIR socket on `ctx`.
  SubReconnector(zmq::context_t& ctx, zmq::socket_t& sub);

  /// Connects again to every endpoint libzmq gave up on; at least once a second, on the
  /// socket's thread.
  void check(zmq::socket_t& sub);
  void close() { monitor_.close(); }

 private:
  zmq::socket_t monitor_;
  std::map<std::string, std::chrono::steady_clock::time_point> dropped_;  ///< endpoint -> when
  LogLimiter log_;
};

}  // namespace fq::daemon
