// fqd's HTTP listener ([http] listen): GET /metrics (Prometheus text), /healthz, /streams
// (JSON counters), /streams/ID/latest (the latest result's Draco chunks, for the viewer) and
// the live viewer's files from http.web_root. cpp-httplib (Debian libcpp-httplib-dev) parses and
// answers the requests; HttpFront (http_front.h) holds fqd's bounds in front of it.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "common/non_copyable.h"
#include "common/status.h"
#include "daemon/config/config.h"
#include "daemon/config/live_caps.h"
#include "daemon/http/http_access.h"
#include "daemon/http/http_refusals.h"
#include "daemon/http/tls_context.h"
#include "daemon/stream/latest_results.h"
#include "daemon/stream/stream_registry.h"

namespace fq::daemon {

class HttpFront;

class HttpServer : NonCopyable {
 public:
  /// `healthy` is the daemon's own view (engines made, sockets bound, threads running).
  HttpServer(const DaemonConfig& config, const LiveCaps& caps, StreamRegistry& registry,
             LatestResults& latest, std::vector<std::string> engines, const std::atomic<bool>& healthy);
  ~HttpServer();

  /// Loads the token and TLS files, binds http.listen (port 0: any free port) and serves on a
  /// thread of its own. A second process on the same port fails here (no port sharing).
  Status start();
  /// Applies a reloaded [http]'s token and allowed hosts (SIGHUP; load_http_access made them).
  void set_access(HttpAccessRules rules) { access_.set(std::move(rules)); }
  /// Stops serving and joins; idempotent.
  void stop();
  /// The bound address, "http://host:port" (https with TLS).
  const std::string& url() const { return url_; }
  /// More /metrics text, appended to the streams' (the daemon's service metrics); set
  /// before start().
  void set_extra_metrics(std::function<std::string()> extra) { extra_metrics_ = std::move(extra); }

 private:
  void add_api_routes();
  void add_viewer_routes();
  /// Warnings for a listener other hosts can reach without TLS or a token.
  void warn_if_exposed(const std::string& host) const;
  std::string metrics() const;
  /// What /healthz answers: fqd is up and has an engine.
  bool up() const { return healthy_.load() && !engines_.empty(); }

  const DaemonConfig& config_;
  const LiveCaps& caps_;
  StreamRegistry& registry_;
  LatestResults& latest_;
  std::vector<std::string> engines_;
  std::vector<int> gpus_;  ///< devices with a CUDA engine (for GPU memory metrics)
  const std::atomic<bool>& healthy_;
  HttpRefusalCounters refusals_;
  HttpAccess access_;
  TlsContext tls_;
  std::unique_ptr<HttpFront> server_;
  std::thread thread_;
  std::atomic<bool> listen_returned_{false};
  std::atomic<uint32_t> long_polls_{0};  ///< /latest requests waiting now
  std::string url_;
  std::function<std::string()> extra_metrics_;
};

}  // namespace fq::daemon
