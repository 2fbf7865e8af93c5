// CURVE security for fqd's three sockets: encryption with fqd's key pair, and a ZAP
// handler (ZeroMQ's authentication protocol, RFC 27) that admits only allow-listed client
// public keys. One handler runs per ZeroMQ context.
#pragma once

#include <set>
#include <string>
#include <thread>
#include <vector>
#include <zmq.hpp>

#include "common/curve_keys.h"
#include "common/non_copyable.h"
#include "common/status.h"
#include "daemon/log_limiter.h"
#include "daemon/stream_admission.h"

namespace fq::daemon {

struct SecurityConfig {
  std::string curve_key_file;     ///< fqd's key pair (public + secret); empty: CURVE off
  std::string client_keys_file;   ///< client public keys allowed in; required with CURVE
  bool enabled() const { return !curve_key_file.empty(); }
};

/// The keys a SecurityConfig names, read and checked.
struct CurveServerKeys {
  CurveKeyPair server;
  std::set<std::string> clients;  ///< Z85
};
Status load_curve_server_keys(const SecurityConfig& c, CurveServerKeys& out);

/// Makes `s` a CURVE server with fqd's keys (before bind).
void make_curve_server(zmq::socket_t& s, const CurveKeyPair& server);

/// True when `endpoint` can only be reached from this host (loopback, ipc, inproc).
bool is_local_endpoint(const std::string& endpoint);
/// True for a host name or address of this host only (localhost, 127.x, ::1).
bool is_loopback_host(const std::string& host);

/// Answers ZAP requests on one context: 200 for an allow-listed client key, 400 (counted as
/// a refusal) for anything else.
class ZapHandler : NonCopyable {
 public:
  ZapHandler(zmq::context_t& context, std::set<std::string> allowed, RefusalCounters& refusals);
  ~ZapHandler();
  /// Joins the thread; call after the context was shut down or closed.
  void join();

 private:
  void run(zmq::socket_t socket);

  std::set<std::string> allowed_;
  RefusalCounters& refusals_;
  LogLimiter log_;  ///< one line per refused connection, at most 5 a second
  std::thread thread_;
};

}  // namespace fq::daemon
