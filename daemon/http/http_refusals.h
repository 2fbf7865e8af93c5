// Why fqd's HTTP listener refused a request or a connection (counted on /metrics as
// fq_http_refused_total{reason}).
#pragma once

#include "daemon/stream/reason_counters.h"

namespace fq::daemon {

enum class HttpRefusal {
  kHeadTooLarge,        ///< request line + headers over http.max_head_bytes (431)
  kTooManyHeaders,      ///< more header lines than http.max_headers (431)
  kBody,                ///< a request that carries a body (413): fqd takes none
  kHeadTimeout,         ///< a head not complete within http.request_timeout_s (408)
  kTooManyConnections,  ///< http.max_connections open already (503)
  kTooManyLongPolls,    ///< http.max_long_polls waiting already (503)
  kBadHost,             ///< a Host header outside http.allowed_hosts (421)
  kUnauthenticated,     ///< no or a wrong token (401), or none possible with CURVE on (403)
  kTls,                 ///< a TLS handshake that failed or did not finish in time
  kLoginRate,           ///< /login tried too often from one address (429)
  kTlsRate,             ///< TLS connections from one address past the handshake rate (closed)
  kCount
};

/// The reason's label on /metrics.
inline const char* http_refusal_name(HttpRefusal r) {
  switch (r) {
    case HttpRefusal::kHeadTooLarge:
      return "head_too_large";
    case HttpRefusal::kTooManyHeaders:
      return "too_many_headers";
    case HttpRefusal::kBody:
      return "body";
    case HttpRefusal::kHeadTimeout:
      return "head_timeout";
    case HttpRefusal::kTooManyConnections:
      return "too_many_connections";
    case HttpRefusal::kTooManyLongPolls:
      return "too_many_long_polls";
    case HttpRefusal::kBadHost:
      return "bad_host";
    case HttpRefusal::kUnauthenticated:
      return "unauthenticated";
    case HttpRefusal::kTls:
      return "tls";
    case HttpRefusal::kLoginRate:
      return "login_rate";
    case HttpRefusal::kTlsRate:
      return "tls_rate";
    case HttpRefusal::kCount:
      break;
  }
  return "?";
}

using HttpRefusalCounters = ReasonCounters<HttpRefusal>;

}  // namespace fq::daemon
