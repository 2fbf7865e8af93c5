// Bounds on each subscriber's subscriptions to the publish socket, in number and bytes.
//
// An XPUB keeps every subscription of every subscriber in a byte trie, about 16 bytes per byte
// of topic: 2,000 subscriptions of 60 KB took fqd from 23 to 1,944 MB, and 670 MB stayed after
// the subscriber left. Now a subscription is at most a stream id long (ZMQ_MAXMSGSIZE =
// caps.max_stream_id_bytes + 1, set in result_socket.cpp), and a subscriber past
// caps.max_subscriptions or caps.max_subscription_bytes is refused (counted `subscriptions`) and
// its connection cut, which is what frees what libzmq keeps for it.
//
// ZMQ_XPUB_MANUAL (fqd applying each subscription itself) is not used: in libzmq 4.3.4
// (Debian 12) a manual subscription can land on the pipe of a subscriber that has already left
// (libzmq PR #4137, after 4.3.4), after which a send matches a freed pipe, and a subscriber that
// subscribes and leaves at once makes that happen. With ZMQ_XPUB_VERBOSER libzmq applies
// subscriptions itself and hands fqd every subscribe and unsubscribe, each with the socket it
// came from (ZMQ_SRCFD); fqd keeps each subscriber's topics (bounded by the caps) so that an
// unsubscribe of a topic it never had cannot buy room. What libzmq applies before fqd reads
// it is bounded by the socket's receive mark (RCVHWM messages of at most a stream id each).
// A socket monitor says when a subscriber comes and goes, so its accounting goes with it.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <zmq.hpp>

#include "daemon/pipeline/curve_auth.h"
#include "daemon/pipeline/log_limiter.h"
#include "daemon/stream/stream_admission.h"

namespace fq::daemon {

struct SubscriptionCaps {
  uint32_t max_count = 128;    ///< subscriptions of one subscriber
  uint64_t max_bytes = 16384;  ///< topic bytes of one subscriber's subscriptions
};

class SubscriptionGate {
 public:
  /// Asks `xpub` (before it binds) for every subscription with its source, and returns a PAIR
  /// socket on `ctx` that receives its connection events (for the constructor).
  static zmq::socket_t monitor(zmq::context_t& ctx, zmq::socket_t& xpub);

  /// `keys`: with [security], the client keys allowed now (a subscriber whose key is revoked
  /// is cut at the next drain); null without CURVE.
  SubscriptionGate(zmq::socket_t monitor, SubscriptionCaps caps, RefusalCounters& refusals,
                   const ClientKeys* keys = nullptr)
      : monitor_(std::move(monitor)), caps_(caps), refusals_(&refusals), keys_(keys) {}

  /// Accounts for every subscription message waiting on `xpub`, cutting subscribers over the
  /// caps; on the socket's thread.
  void drain(zmq::socket_t& xpub);
  /// Subscribers fqd accounts for now.
  size_t peers() const { return peers_.size(); }
  void close() { monitor_.close(); }

 private:
  struct Peer {
    std::set<std::string, std::less<>> topics;
    uint64_t bytes = 0;
    bool cut = false;  ///< refused: its remaining messages are ignored until it is gone
    std::string key;   ///< its CURVE client key
  };
  void connection_events();
  void subscription(const zmq::message_t& m);
  /// Cuts the subscriber on socket `fd` (shutdown: libzmq then drops it and what it subscribed).
  void cut(int fd, Peer& peer);
  /// After the allowed keys changed: cuts every subscriber whose key is no longer allowed.
  void revoke();

  zmq::socket_t monitor_;  ///< PAIR: ACCEPTED and DISCONNECTED events of the XPUB
  SubscriptionCaps caps_;
  RefusalCounters* refusals_;
  const ClientKeys* keys_;
  uint64_t keys_seen_ = 0;     ///< keys_->generation() at the last revoke()
  std::map<int, Peer> peers_;  ///< by socket
  std::unique_ptr<LogLimiter> log_ = std::make_unique<LogLimiter>();  // movable with the gate
};

}  // namespace fq::daemon
