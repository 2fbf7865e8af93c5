// The SUB side of fqd's ingest ([ingest] connect): one SUB socket per producer, and a new one
// for a producer that libzmq gave up on. libzmq 4.3 gives a connecting socket up for good when
// its peer breaks the protocol (a part over ZMQ_MAXMSGSIZE, a failed CURVE handshake), and keeps
// the endpoint with pointers to the connection it freed: connecting to it again does nothing,
// and zmq_disconnect of it works on freed memory. fqd did that, on one socket shared by every
// producer, and it ended the connection just made to another producer whenever that connection
// had taken the freed place: that producer then never came back. Closing a socket touches only
// its live connections, so a fresh socket is the safe way back.
// A monitor of each socket tells the cases apart: after an ordinary disconnect libzmq says at
// once that it retries (ZMQ_EVENT_CONNECT_RETRIED); when it has not said so within a second,
// fqd replaces the socket (so at most once a second per producer).
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>
#include <zmq.hpp>

#include "common/curve_keys.h"
#include "common/non_copyable.h"
#include "common/status.h"
#include "daemon/pipeline/log_limiter.h"

namespace fq::daemon {

/// What every producer's SUB socket is made with.
struct SubSocketRules {
  std::vector<std::string> streams;          ///< subscriptions; empty: every stream
  uint64_t max_frame_bytes = 0;              ///< ZMQ_MAXMSGSIZE: a larger part drops the connection
  std::optional<CurveKeyPair> curve_server;  ///< fqd's keys ([security]): producers authenticate (ZAP)
};

class SubProducers : NonCopyable {
 public:
  /// `replaced` counts the sockets made anew (fq_ingest_reconnects_total) and outlives this.
  SubProducers(zmq::context_t& ctx, SubSocketRules rules, std::atomic<uint64_t>& replaced);

  /// A socket connected to `endpoint`; kInvalidArgument for an endpoint ZeroMQ refuses.
  Status add(const std::string& endpoint);
  /// Gives every producer that libzmq gave up on a new socket; at least once a second, on the
  /// thread that reads the sockets (sockets change, so poll items are made again after it).
  void check();

  size_t size() const { return producers_.size(); }
  zmq::socket_t& socket(size_t i) { return producers_[i].sub; }
  void close();

 private:
  struct Producer {
    std::string endpoint;
    zmq::socket_t sub, monitor;
    std::optional<std::chrono::steady_clock::time_point> dropped;  ///< disconnected, no retry said
  };
  /// Makes `p`'s socket and its monitor and connects it (zmq::error_t when ZeroMQ refuses).
  void open(Producer& p);

  zmq::context_t& ctx_;
  SubSocketRules rules_;
  std::atomic<uint64_t>& replaced_;
  std::vector<Producer> producers_;
  LogLimiter log_;
};

}  // namespace fq::daemon
