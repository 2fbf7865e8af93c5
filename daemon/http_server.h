// fqd's HTTP listener ([http] listen): GET /metrics (Prometheus text), /healthz, /streams
// (JSON counters), /streams/ID/latest (the latest result's Draco chunks, for the viewer) and
// the live viewer's files from http.web_root. cpp-httplib (Debian libcpp-httplib-dev) does the
// HTTP: a small, well-kept server with its own thread pool, so no HTTP is hand-written here.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "common/non_copyable.h"
#include "common/status.h"
#include "daemon/config.h"
#include "daemon/latest_results.h"
#include "daemon/stream_registry.h"

namespace httplib {
class Server;
}

namespace fq::daemon {

class HttpServer : NonCopyable {
 public:
  /// `healthy` is the daemon's own view (engines made, sockets bound, threads running).
  HttpServer(const DaemonConfig& config, StreamRegistry& registry, LatestResults& latest,
             std::vector<std::string> engines, const std::atomic<bool>& healthy);
  ~HttpServer();

  /// Binds http.listen (port 0: any free port) and serves on a thread of its own.
  Status start();
  /// Stops serving and joins; idempotent.
  void stop();
  /// The bound address, "http://host:port".
  const std::string& url() const { return url_; }
  /// More /metrics text, appended to the streams' (the daemon's service metrics); set
  /// before start().
  void set_extra_metrics(std::function<std::string()> extra) { extra_metrics_ = std::move(extra); }

 private:
  void add_api_routes();
  void add_viewer_routes();
  std::string metrics() const;

  const DaemonConfig& config_;
  StreamRegistry& registry_;
  LatestResults& latest_;
  std::vector<std::string> engines_;
  std::vector<int> gpus_;  ///< devices with a CUDA engine (for GPU memory metrics)
  const std::atomic<bool>& healthy_;
  std::unique_ptr<httplib::Server> server_;
  std::thread thread_;
  std::atomic<bool> listen_returned_{false};
  std::string url_;
  std::function<std::string()> extra_metrics_;
};

}  // namespace fq::daemon
