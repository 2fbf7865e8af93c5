// Who may use fqd's HTTP listener, decided before routing:
//  - the Host header must name this server (a DNS-rebinding page in a browser sends its own
//    name): http.allowed_hosts, or by default loopback names, IP literals and the listen host;
//  - with http.token_file set, every path but /healthz needs the token, as
//    "Authorization: Bearer TOKEN", or the session cookie that GET /login?token=TOKEN sets (for
//    the viewer, whose requests then carry it; http_sessions.h): a random id, not the token;
//  - /login is tried at most kLoginBurst times at once and kLoginPerSecond a second per source
//    address (429 with Retry-After past it), and every failure is logged (at most 5 lines a
//    second);
//  - with [security] (CURVE) on and no token, only /metrics and /healthz answer: the streams,
//    their geometry and the viewer are never served unauthenticated.
// Thread-safe; SIGHUP replaces the rules (a new token, new hosts) without a restart.
#pragma once

#include <httplib.h>

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "common/status.h"
#include "daemon/config/http_config.h"
#include "daemon/http/http_refusals.h"
#include "daemon/http/http_sessions.h"
#include "daemon/http/source_rate.h"
#include "daemon/pipeline/log_limiter.h"

namespace fq::daemon {

struct HttpAccessRules {
  std::string token;                       ///< empty: no token
  std::vector<std::string> allowed_hosts;  ///< http.allowed_hosts; empty: the default set
  std::string listen_host;                 ///< http.listen's host (allowed by default)
  bool curve_on = false;                   ///< [security] on: no unauthenticated geometry
  bool tls = false;                        ///< cookies are marked Secure
};

/// The rules of `http` (the token read from http.token_file) for a daemon with CURVE
/// `curve_on`; an error names the token file and what is wrong with it.
Status load_http_access(const HttpConfig& http, bool curve_on, HttpAccessRules& out);

/// The token of a token file (its first line, trailing space removed); an error says what is
/// wrong (unreadable, too short, a character a header or cookie cannot carry), not which key.
Status read_http_token(const std::string& path, std::string& token);

/// True when `host` (a Host header value, port included or not) is allowed by `rules`.
bool host_allowed(const std::string& host, const HttpAccessRules& rules);

/// Login attempts per source address: at once, then a second (a token bucket).
inline constexpr double kLoginBurst = 5;
inline constexpr double kLoginPerSecond = 1;

class HttpAccess {
 public:
  explicit HttpAccess(HttpAccessRules rules)
      : rules_(std::make_shared<const HttpAccessRules>(std::move(rules))) {}
  /// New rules; a new token ends every login session.
  void set(HttpAccessRules rules);

  /// Answers /login and refused requests (Handled, counted by reason); Unhandled lets the
  /// request through to its route.
  httplib::Server::HandlerResponse check(const httplib::Request& req, httplib::Response& res,
                                         HttpRefusalCounters& refusals);

 private:
  std::shared_ptr<const HttpAccessRules> rules() const;
  httplib::Server::HandlerResponse login(const httplib::Request& req, httplib::Response& res,
                                         const HttpAccessRules& rules, HttpRefusalCounters& refusals);
  bool authorized(const httplib::Request& req, const HttpAccessRules& rules) const;

  mutable std::mutex mutex_;
  std::shared_ptr<const HttpAccessRules> rules_;
  HttpSessions sessions_;
  SourceRate login_rate_{kLoginPerSecond, kLoginBurst};
  LogLimiter login_log_;
};

}  // namespace fq::daemon
