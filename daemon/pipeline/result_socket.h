// fqd's publish socket: an XPUB that bounds what it queues for each subscriber and says when
// a subscriber missed a result.
//
// ZeroMQ's high-water mark counts messages (a multipart result counts once), so the bound is
// in results: SNDHWM = caps.max_subscriber_results, fixed when the socket is made. What fqd
// holds for a subscriber that does not read is then at most that many results in its queue,
// one more being written by ZeroMQ's I/O thread, and the kernel send buffer (set here, not
// autotuned): (max_subscriber_results + 1) x the largest result + kSendBufferBytes. Queued
// results are shared, not copied, between subscribers, so several slow subscribers together
// hold no more results than one. The mark is not changed while subscribers are connected:
// ZeroMQ applies a lower mark to connected pipes, but its reader-side count lags, so a
// subscriber that has read everything can look full and stop getting results.
//
// PUB drops silently for a full subscriber; with ZMQ_XPUB_NODROP an XPUB refuses the whole
// send (EAGAIN) when any matching subscriber is full. The socket sends that way first, and
// when refused reports an overflow and sends it again without NODROP, which delivers it to
// every subscriber with room. ZeroMQ then leaves the full subscriber out of later sends
// (without a word) until it has read half its queue, so an overflow is counted once per
// episode, not per missed result; which subscriber it was ZeroMQ does not tell.
#pragma once

#include <vector>
#include <zmq.hpp>

#include "daemon/pipeline/subscription_gate.h"

namespace fq::daemon {

class ResultSocket {
 public:
  /// The kernel send buffer of each subscriber connection (Linux books up to twice this).
  static constexpr int kSendBufferBytes = 2 << 20;
  /// The smallest ZMQ_MAXMSGSIZE: the CURVE handshake's commands must fit.
  static constexpr int64_t kMinMessageBytes = 1024;
  /// The receive mark: subscription messages of one subscriber libzmq holds at once.
  static constexpr int kSubscriptionsInFlight = 64;

  /// Sets the options of a new XPUB socket (before bind): `max_results` queued per subscriber,
  /// subscriptions of at most `max_topic_bytes` (a longer one drops the subscriber's
  /// connection before it is buffered).
  static void configure(zmq::socket_t& xpub, int max_results, uint32_t max_topic_bytes);

  /// `monitor` from SubscriptionGate::monitor(xpub), made before the socket bound.
  ResultSocket(zmq::socket_t xpub, zmq::socket_t monitor, SubscriptionCaps caps, RefusalCounters& refusals,
               const ClientKeys* keys = nullptr)
      : socket_(std::move(xpub)), gate_(std::move(monitor), caps, refusals, keys) {}

  /// Sends one multipart result without blocking. False when a subscriber's queue was found
  /// full (an overflow: it did not get this result; the others did).
  bool send(const std::vector<zmq::const_buffer>& parts);
  /// Reads the subscription messages XPUB hands up, bounding each subscriber's (subscription_gate.h).
  void drain_subscriptions() { gate_.drain(socket_); }
  void close() {
    gate_.close();
    socket_.close();
  }

 private:
  bool try_send(const std::vector<zmq::const_buffer>& parts);

  zmq::socket_t socket_;
  SubscriptionGate gate_;
};

}  // namespace fq::daemon
