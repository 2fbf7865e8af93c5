// The open connections of fqd's HTTP listener, each served on a thread of its own, at most
// http.max_connections at once.
//
// cpp-httplib 0.11 serves connections from a pool of 8 threads fed by an unbounded queue, and a
// thread stays with its connection while it waits for bytes: 8 slowloris connections (or 200
// that connect and say nothing) held every thread, /healthz went unanswered for 20 s and
// SIGTERM waited for them. Here a connection holds only its own thread, for at most the time
// its bounds allow (http.request_timeout_s for a head, http.idle_timeout_s between requests),
// one over the bound is answered 503 at once, and close_all() ends every connection at once
// (their blocked reads and writes fail), so that stopping takes no longer than a handler.
//
// Past the bound a health probe is still answered (a Kubernetes liveness probe that failed
// here restarted a healthy pod while 300 connections were held): up to kHealthLane connections
// over the bound are read on a lane of their own for at most kHealthLaneHead, and `GET
// /healthz` there gets the health answer; anything else the 503. Plain-text listeners only (a
// TLS probe would need the handshake first).
#pragma once

#include <condition_variable>
#include <functional>
#include <mutex>
#include <set>
#include <string>

#include "common/non_copyable.h"
#include "daemon/http/http_refusals.h"

namespace fq::daemon {

class HttpConnections : NonCopyable {
 public:
  /// `serve` runs a connection to its end; the socket is closed after it returns.
  HttpConnections(uint32_t max_connections, HttpRefusalCounters& refusals, std::function<void(int fd)> serve);
  /// close_all().
  ~HttpConnections();

  /// Takes `fd` (a freshly accepted socket): served on a new thread, or answered 503 and
  /// closed when `max_connections` are open or the listener is closing.
  void open(int fd);
  /// Shuts every open connection down (their reads and writes fail at once), waits for their
  /// threads, and refuses later connections.
  void close_all();
  /// Connections open now.
  size_t open_count() const;
  /// Whether a refused connection gets a plain-text 503 (not on a TLS listener); before use.
  void set_answer_refusals(bool answer) { answer_refusals_ = answer; }
  /// Whether fqd is healthy, for the health lane (none: no lane); before use.
  void set_health(std::function<bool()> healthy) { healthy_ = std::move(healthy); }

  /// Connections over the bound read at once on the health lane, and how long each may take
  /// to send its request line.
  static constexpr size_t kHealthLane = 16;
  static constexpr int kHealthLaneHeadMs = 500;

 private:
  void run(int fd);
  void refuse(int fd);
  /// The health lane: reads the request line; /healthz gets the health answer, the rest 503.
  void answer_on_lane(int fd);

  const uint32_t max_connections_;
  HttpRefusalCounters& refusals_;
  std::function<void(int)> serve_;
  mutable std::mutex mutex_;
  std::condition_variable finished_;
  std::set<int> open_;  ///< sockets being served (shut down by close_all)
  size_t threads_ = 0;  ///< threads still running (they outlive their socket briefly)
  size_t lane_ = 0;     ///< connections on the health lane now
  std::function<bool()> healthy_;
  bool closing_ = false;
  bool answer_refusals_ = true;
};

}  // namespace fq::daemon
