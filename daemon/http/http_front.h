// cpp-httplib's Server with fqd's bounds in front of its parser: connections are served on
// threads of their own, at most http.max_connections (http_connections.h), each through an
// HttpStream (bounded request heads, timeouts); requests that carry a body are refused without
// reading it (fqd has no route that takes one); the listening socket does not share its port
// (the library sets SO_REUSEPORT, which let a second fqd bind the same port and take half the
// requests).
//
// The library serves a connection in Server::process_and_close_socket, a virtual that its own
// SSLServer overrides the same way: the keep-alive loop here calls the library's
// process_request for each request, so routing, handlers and responses stay the library's.
#pragma once

#include <httplib.h>

#include <chrono>
#include <functional>

#include "daemon/config/http_config.h"
#include "daemon/http/http_connections.h"
#include "daemon/http/http_refusals.h"
#include "daemon/http/http_stream.h"
#include "daemon/http/source_rate.h"
#include "daemon/pipeline/log_limiter.h"

namespace fq::daemon {

/// TLS handshakes per source address: at once, then a second (a token bucket). A handshake costs
/// fqd a private-key operation (about a millisecond of CPU for RSA 2048), which a peer can ask
/// for as fast as it connects; a viewer opens a few connections, a proxy more.
inline constexpr double kTlsHandshakeBurst = 64;
inline constexpr double kTlsHandshakesPerSecond = 32;

class HttpFront : public httplib::Server {
 public:
  HttpFront(const HttpConfig& config, HttpRefusalCounters& refusals);
  /// close_connections().
  ~HttpFront() override;

  /// Runs before routing for every request that passed fqd's own checks (a body, ...);
  /// Handled ends the request with the response it set.
  void set_request_check(HandlerWithResponse check) { check_ = std::move(check); }
  /// What a health probe past max_connections is answered (HttpConnections' health lane).
  void set_health(std::function<bool()> healthy) { connections_.set_health(std::move(healthy)); }
  /// Serves TLS with `tls` (owned by the caller, alive while this serves); before binding.
  void set_tls(SSL_CTX* tls);
  /// Binds host:port (0: any free port) and listens; the bound port, or -1.
  int bind_listener(const std::string& host, int port);
  /// Ends every open connection and waits for their threads (after stop(): none come after).
  void close_connections() { connections_.close_all(); }

 private:
  /// On the accept thread (the task queue runs tasks where they are queued): hands the
  /// socket to a connection thread, or refuses it.
  bool process_and_close_socket(int sock) override;
  /// Serves requests on `fd` until the peer closes, a bound is hit or the keep-alive ends.
  void serve(int fd);
  /// The per-source TLS handshake rate (counted and logged when past it).
  bool handshake_allowed(const HttpStream& stream);
  HandlerResponse pre_routing(const httplib::Request& req, httplib::Response& res);

  SSL_CTX* tls_ = nullptr;
  HttpStream::HeadLimits head_limits_;
  std::chrono::milliseconds io_timeout_, idle_timeout_;
  HttpRefusalCounters& refusals_;
  HandlerWithResponse check_;
  SourceRate tls_rate_{kTlsHandshakesPerSecond, kTlsHandshakeBurst};
  LogLimiter tls_rate_log_;
  HttpConnections connections_;  // last: its threads use the members above
};

}  // namespace fq::daemon
