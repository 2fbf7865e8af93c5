// cpp-httplib's Server with fqd's bounds in front of its parser: each connection is served
// through an HttpStream (bounded request heads), requests that carry a body are refused
// without reading it (fqd has no route that takes one), and the listening socket does not
// share its port (the library sets SO_REUSEPORT, which let a second fqd bind the same port and
// take half the requests).
//
// The library serves a connection in Server::process_and_close_socket, a virtual that its own
// SSLServer overrides the same way: the keep-alive loop here calls the library's
// process_request for each request, so routing, handlers and responses stay the library's.
#pragma once

#include <httplib.h>

#include <chrono>

#include "daemon/http_config.h"
#include "daemon/http_refusals.h"
#include "daemon/http_stream.h"

namespace fq::daemon {

class HttpFront : public httplib::Server {
 public:
  HttpFront(const HttpConfig& config, HttpRefusalCounters& refusals);

  /// Runs before routing for every request that passed fqd's own checks (a body, ...);
  /// Handled ends the request with the response it set.
  void set_request_check(HandlerWithResponse check) { check_ = std::move(check); }

 private:
  bool process_and_close_socket(int sock) override;
  /// Serves requests on `fd` until the peer closes, a bound is hit or the keep-alive ends.
  void serve(int fd);
  HandlerResponse pre_routing(const httplib::Request& req, httplib::Response& res);

  HttpStream::HeadLimits head_limits_;
  HttpRefusalCounters& refusals_;
  HandlerWithResponse check_;
};

}  // namespace fq::daemon
