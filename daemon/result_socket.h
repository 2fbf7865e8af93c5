// fqd's publish socket: an XPUB that bounds what it queues for each subscriber in bytes and
// says when a subscriber missed a result.
//
// ZeroMQ's high-water mark counts messages (a multipart message counts once), so a bytes
// bound is a message bound derived from the largest result so far: SNDHWM =
// clamp(max_subscriber_bytes / largest, 1, kMaxHwm). The largest result only grows, and each
// queued result was at most the largest at the time it was queued, so a subscriber's queue
// never holds more than max(max_subscriber_bytes, largest) (docs/DAEMON.md has the whole
// formula). ZeroMQ applies a changed SNDHWM to connected subscribers too.
//
// PUB drops silently for a full subscriber; with ZMQ_XPUB_NODROP an XPUB refuses the whole
// send (EAGAIN) when any matching subscriber is full. The socket sends that way first, and
// when refused counts the result as missed and sends it again without NODROP, which delivers
// it to every subscriber with room. Which subscriber missed it ZeroMQ does not tell.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>
#include <zmq.hpp>

namespace fq::daemon {

class ResultSocket {
 public:
  /// ZeroMQ's default SNDHWM: small results queue as many as before.
  static constexpr int kMaxHwm = 1000;
  /// Per message part: ZeroMQ's message header and queue slot, on top of the bytes.
  static constexpr size_t kPartOverhead = 128;
  /// The kernel send buffer of each subscriber connection (Linux books up to twice this).
  static constexpr int kSendBufferBytes = 2 << 20;

  /// Sets the options of a new XPUB socket (before bind).
  static void configure(zmq::socket_t& xpub);

  ResultSocket(zmq::socket_t xpub, uint64_t max_subscriber_bytes)
      : socket_(std::move(xpub)), max_bytes_(max_subscriber_bytes) {}

  /// Sends one multipart result without blocking. False when some subscriber's queue was
  /// full, so that it did not get this result (the others did).
  bool send(const std::vector<zmq::const_buffer>& parts);
  /// Reads the subscription messages XPUB hands up (they would pile up unread).
  void drain_subscriptions();
  /// The send high-water mark in force.
  int hwm() const { return hwm_; }
  void close() { socket_.close(); }

 private:
  void fit_hwm(size_t message_bytes);
  bool try_send(const std::vector<zmq::const_buffer>& parts);

  zmq::socket_t socket_;
  uint64_t max_bytes_;
  size_t largest_ = 0;
  int hwm_ = kMaxHwm;
};

}  // namespace fq::daemon
