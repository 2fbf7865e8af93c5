// fqd as an object: binds its sockets, starts its threads, and drains them on stop().
// main.cpp runs one; tests and fqstreambench run one in-process on ephemeral ports.
#pragma once

#include <atomic>
#include <memory>
#include <string>
#include <thread>
#include <vector>
#include <zmq.hpp>

#include "common/non_copyable.h"
#include "daemon/config/config.h"
#include "daemon/control/stats_log.h"
#include "daemon/http/http_server.h"
#include "daemon/pipeline/ingest.h"
#include "daemon/pipeline/pipeline.h"
#include "daemon/stream/stream_registry.h"
#include "kernels/engine.h"

namespace fq::daemon {

/// The addresses actually bound (a "*" port in the config is resolved here).
struct BoundEndpoints {
  std::string ingest, publish, control;
  std::string http;  ///< "http://host:port", empty without an HTTP listener
};

/// One engine per listed GPU (CUDA), plus or else `cpu_engines` CPU engines, as the config says.
/// kUnavailable when an explicitly requested CUDA engine cannot be made.
StatusOr<std::vector<std::unique_ptr<Engine>>> make_engines(const EngineConfig& config);

class Daemon : NonCopyable {
 public:
  explicit Daemon(DaemonConfig config);
  ~Daemon();

  /// Makes the engines, binds the three sockets and starts every thread.
  Status start();
  /// Stops receiving, finishes every frame already received (results are published),
  /// and joins all threads. Idempotent; also called by the destructor.
  void stop();

  const BoundEndpoints& endpoints() const { return endpoints_; }
  const DaemonConfig& config() const { return config_; }
  /// Applies a reloaded configuration (SIGHUP) to the running daemon: every setting a reload
  /// can change (config_reload.h) at once, or nothing: an error names the restart-only settings
  /// `fresh` changes, or what is wrong with a file it names (the client keys, the token).
  Status reload(const DaemonConfig& fresh);
  StreamRegistry& registry() { return registry_; }
  /// Names of the engines in use ("cpu", "cuda:<device>").
  std::vector<std::string> engine_names() const;
  /// The /metrics families about the service (service_metrics.h): refusals, budgets,
  /// engine busy time, queue depths, the process.
  std::string service_metrics() const;
  /// Host CPU so far, by stage and of all of fqd's threads (fq_stage_cpu_seconds_total and
  /// fq_cpu_seconds_total on /metrics).
  CpuUsage cpu_usage() const;

 private:
  struct Sockets;  // made and bound by start(), then handed to their threads
  Status bind_sockets(Sockets& s);
  Status make_sockets(Sockets& s);

  DaemonConfig config_;
  StreamRegistry registry_;
  LiveCaps caps_;
  Pipeline pipeline_;
  std::vector<std::unique_ptr<Engine>> engines_;
  std::unique_ptr<ClientKeys> client_keys_;   ///< with [security]; outlives the ZAP handlers
  std::unique_ptr<ClientKeys> control_keys_;  ///< with security.control_keys_file; likewise
  // Declared before the contexts, so destroyed after them: closing a context ends its
  // handler's thread.
  std::unique_ptr<ZapHandler> input_zap_, output_zap_;
  zmq::context_t input_context_;   // ingest + control: shut down first
  zmq::context_t output_context_;  // publish: closed after the pipeline drained
  BoundEndpoints endpoints_;
  std::unique_ptr<Ingest> ingest_;  ///< the ingest thread and its sockets
  std::thread control_thread_, publisher_thread_;
  std::vector<std::thread> decoders_, workers_, encoders_;
  bool running_ = false;
  std::atomic<bool> healthy_{false};         ///< every thread started (GET /healthz)
  std::atomic<uint64_t> sub_reconnects_{0};  ///< SUB producers connected again (fq_ingest_reconnects_total)
  std::unique_ptr<HttpServer> http_;         ///< null when http.listen is empty
  std::unique_ptr<StatsLog> stats_log_;      ///< null when stats.interval_s is 0
};

}  // namespace fq::daemon
