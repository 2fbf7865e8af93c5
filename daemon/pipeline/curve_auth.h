// CURVE security for fqd's three sockets: encryption with fqd's key pair, and a ZAP
// handler (ZeroMQ's authentication protocol, RFC 27) that admits only allow-listed client
// public keys. One handler runs per ZeroMQ context. The control socket may have a list of its
// own (security.control_keys_file): operators' keys, which producers and consumers lack.
#pragma once

#include <atomic>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>
#include <zmq.hpp>

#include "common/curve_keys.h"
#include "common/non_copyable.h"
#include "common/status.h"
#include "daemon/config/security_config.h"
#include "daemon/pipeline/log_limiter.h"
#include "daemon/stream/stream_admission.h"

namespace fq::daemon {

/// The keys a SecurityConfig names, read and checked.
struct CurveServerKeys {
  CurveKeyPair server;
  std::set<std::string> clients;  ///< Z85
  std::set<std::string> control;  ///< Z85, control_keys_file's; empty without one
};
Status load_curve_server_keys(const SecurityConfig& c, CurveServerKeys& out);

/// The ZAP domains: the control socket's is its own when it has its own key list.
inline constexpr const char* kZapDomain = "fq";
inline constexpr const char* kControlZapDomain = "fq-control";

/// Makes `s` a CURVE server with fqd's keys (before bind), authenticated in ZAP `domain`.
void make_curve_server(zmq::socket_t& s, const CurveKeyPair& server, const char* domain = kZapDomain);

/// True when `endpoint` can only be reached from this host (loopback, ipc, inproc).
bool is_local_endpoint(const std::string& endpoint);
/// True for a host name or address of this host only (localhost, 127.x, ::1).
bool is_loopback_host(const std::string& host);

/// The client keys allowed in now (security.client_keys_file), replaced when SIGHUP reloads
/// it. Thread-safe.
class ClientKeys : NonCopyable {
 public:
  explicit ClientKeys(std::set<std::string> keys)
      : keys_(std::make_shared<const std::set<std::string>>(std::move(keys))) {}
  bool allowed(const std::string& key) const;
  void set(std::set<std::string> keys);
  /// Changes with every set(): a holder of connections checks them again when it moves.
  uint64_t generation() const { return generation_.load(); }

 private:
  mutable std::mutex mutex_;
  std::shared_ptr<const std::set<std::string>> keys_;
  std::atomic<uint64_t> generation_{0};
};

/// The client key (Z85) a message came with over CURVE ("User-Id", as the ZAP handler
/// answered); empty without one.
std::string sender_key(const zmq::message_t& m);

/// Ends the connection a message came over (ZMQ_SRCFD): shut down, not closed, so the socket
/// stays libzmq's, which sees the end and drops the peer. Revoked keys lose their connections
/// this way, since CURVE authenticates a connection only when it starts.
void cut_sender(const zmq::message_t& m);

/// True when `m` came from a client whose key is allowed now, or `keys` is null (no CURVE);
/// otherwise counts an unauthenticated refusal, cuts the connection and returns false.
bool admit_sender(const zmq::message_t& m, const ClientKeys* keys, RefusalCounters& refusals);

/// Answers ZAP requests on one context: 200 for an allow-listed client key, 400 (counted as
/// a refusal) for anything else. Requests of kControlZapDomain are checked against `control`
/// when given, every other request against `allowed`.
class ZapHandler : NonCopyable {
 public:
  ZapHandler(zmq::context_t& context, const ClientKeys& allowed, RefusalCounters& refusals,
             const ClientKeys* control = nullptr);
  ~ZapHandler();
  /// Joins the thread; call after the context was shut down or closed.
  void join();

 private:
  void run(zmq::socket_t socket);

  const ClientKeys& allowed_;
  const ClientKeys* control_;
  RefusalCounters& refusals_;
  LogLimiter log_;  ///< one line per refused connection, at most 5 a second
  std::thread thread_;
};

}  // namespace fq::daemon
