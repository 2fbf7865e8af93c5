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
#pragma once

#include <condition_variable>
#include <functional>
#include <mutex>
#include <set>

#include "common/non_copyable.h"
#include "daemon/http_refusals.h"

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

 private:
  void run(int fd);
  void refuse(int fd);

  const uint32_t max_connections_;
  HttpRefusalCounters& refusals_;
  std::function<void(int)> serve_;
  mutable std::mutex mutex_;
  std::condition_variable finished_;
  std::set<int> open_;  ///< sockets being served (shut down by close_all)
  size_t threads_ = 0;  ///< threads still running (they outlive their socket briefly)
  bool closing_ = false;
  bool answer_refusals_ = true;
};

}  // namespace fq::daemon
