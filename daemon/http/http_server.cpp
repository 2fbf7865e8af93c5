#include "daemon/http/http_server.h"

#include <httplib.h>
#include <spdlog/spdlog.h>

#include <bit>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string_view>
#include <vector>

#include "daemon/control/control_server.h"
#include "daemon/control/counters_json.h"
#include "daemon/control/prometheus_text.h"
#include "daemon/http/http_front.h"
#include "daemon/pipeline/curve_auth.h"

namespace fq::daemon {
namespace {

// A viewer's long poll waits at most this long for a newer result, then gets 204.
constexpr int kMaxWaitMs = 5000;

// The files the viewer needs: its page, and three.js with the Draco decoder from npm.
bool viewer_installed(const std::filesystem::path& root) {
  return std::filesystem::is_regular_file(root / "index.html") &&
         std::filesystem::is_regular_file(root / "node_modules/three/build/three.module.js") &&
         std::filesystem::is_regular_file(root /
                                          "node_modules/three/examples/jsm/libs/draco/draco_decoder.js");
}

std::string chunk_sizes(const LatestResult& r) {
  std::string s;
  for (const std::string& c : r.chunks) s += (s.empty() ? "" : ",") + std::to_string(c.size());
  return s;
}

// Browsers read the arrays in their own byte order, little-endian on every platform they run on.
static_assert(std::endian::native == std::endian::little,
              "the viewer's arrays are sent as little-endian words");

// One waiting long poll, counted while it lives; not admitted past `max`.
class LongPollTicket {
 public:
  LongPollTicket(std::atomic<uint32_t>& count, uint32_t max) : count_(count) {
    admitted_ = count_.fetch_add(1) < max;
  }
  ~LongPollTicket() { count_.fetch_sub(1); }
  LongPollTicket(const LongPollTicket&) = delete;
  LongPollTicket& operator=(const LongPollTicket&) = delete;
  bool admitted() const { return admitted_; }

 private:
  std::atomic<uint32_t>& count_;
  bool admitted_ = false;
};

// The body is [faces][labels][chunks]: the two little-endian uint32 arrays first, so that
// the browser views them in place (a Uint32Array needs a 4-byte aligned offset), then the
// Draco chunks as published. The faces are left out when the viewer already has them
// (`faces=ID` equal to X-Fq-Faces-Id): a stream's faces rarely change.
// The pieces are sent from the kept result itself, which the response holds until the last
// byte is written: no request copies the body (a 25 MB result read by 64 slow viewers once
// held 64 copies), and a newer result replaces the stream's without touching those in flight.
void send_latest(std::shared_ptr<const LatestResult> r, uint64_t viewer_faces_id, httplib::Response& res) {
  const wire::ResultHeader& h = r->header;
  const bool send_faces = r->faces && r->faces_id != viewer_faces_id;
  const size_t face_words = send_faces ? r->faces->size() : 0;
  res.set_header("Cache-Control", "no-store");
  res.set_header("X-Fq-Index", std::to_string(r->index));
  res.set_header("X-Fq-Sequence", std::to_string(h.sequence()));
  res.set_header("X-Fq-Form", h.form() == wire::MESH ? "mesh" : "positions");
  res.set_header("X-Fq-Faces-Id", std::to_string(r->faces_id));
  res.set_header("X-Fq-Faces-Bytes", std::to_string(face_words * sizeof(uint32_t)));
  res.set_header("X-Fq-Labels-Bytes", std::to_string(h.labels_size() * sizeof(uint32_t)));
  res.set_header("X-Fq-Chunk-Sizes", chunk_sizes(*r));
  res.set_header("X-Fq-Vertex-Count", std::to_string(h.vertex_count()));
  res.set_header("X-Fq-Cluster-Count", std::to_string(h.cluster_count()));
  res.set_header("X-Fq-Latency-Ms", std::to_string(h.latency_ms()));
  res.set_header("X-Fq-Late", h.status() == wire::LATE ? "1" : "0");
  res.set_header("X-Fq-Engine", h.engine());
  std::vector<std::string_view> pieces;
  if (send_faces)
    pieces.emplace_back(reinterpret_cast<const char*>(r->faces->data()), face_words * sizeof(uint32_t));
  pieces.emplace_back(reinterpret_cast<const char*>(h.labels().data()), h.labels_size() * sizeof(uint32_t));
  for (const std::string& c : r->chunks) pieces.emplace_back(c);
  size_t total = 0;
  for (const std::string_view& p : pieces) total += p.size();
  if (total == 0) {
    res.set_content("", "application/octet-stream");
    return;
  }
  res.set_content_provider(
      total, "application/octet-stream",
      [r = std::move(r), pieces = std::move(pieces)](size_t offset, size_t length, httplib::DataSink& sink) {
        // The piece holding `offset`, written from there to its end or `length` (httplib asks
        // again from where the write left off).
        for (const std::string_view& p : pieces) {
          if (offset < p.size()) return sink.write(p.data() + offset, std::min(length, p.size() - offset));
          offset -= p.size();
        }
        return false;
      });
}

}  // namespace

HttpServer::HttpServer(const DaemonConfig& config, const LiveCaps& caps, StreamRegistry& registry,
                       LatestResults& latest, std::vector<std::string> engines,
                       const std::atomic<bool>& healthy)
    : config_(config),
      caps_(caps),
      registry_(registry),
      latest_(latest),
      engines_(std::move(engines)),
      healthy_(healthy),
      access_(HttpAccessRules{}),
      server_(std::make_unique<HttpFront>(config.http, refusals_)) {
  for (const std::string& e : engines_)
    if (e.rfind("cuda", 0) == 0) gpus_ = config.engine.gpus;
  server_->set_health([this] { return up(); });  // the probe's lane past max_connections
}

HttpServer::~HttpServer() { stop(); }

std::string HttpServer::metrics() const {
  MetricsInput in;
  registry_.metric_series(wall_ns(), caps_.get()->metric_series_idle_s, in.series, in.other);
  in.streams = registry_.list().size();
  in.engines = engines_;
  in.gpus = gpu_memory(gpus_);
  for (size_t r = 0; r < HttpRefusalCounters::kReasons; ++r)
    in.http_refusals.emplace_back(http_refusal_name(HttpRefusal(r)), refusals_.get(HttpRefusal(r)));
  return extra_metrics_ ? prometheus_text(in) + extra_metrics_() : prometheus_text(in);
}

void HttpServer::add_api_routes() {
  httplib::Server& s = *server_;
  s.Get("/metrics", [this](const httplib::Request&, httplib::Response& res) {
    res.set_content(metrics(), "text/plain; version=0.0.4; charset=utf-8");
  });
  s.Get("/healthz", [this](const httplib::Request&, httplib::Response& res) {
    const bool healthy = up();
    res.status = healthy ? 200 : 503;
    res.set_content(healthy ? "ok\n" : "not ready\n", "text/plain");
  });
  s.Get("/streams", [this](const httplib::Request&, httplib::Response& res) {
    wire::ControlRequest q;
    q.mutable_get_counters();
    nlohmann::json j = counters_json(handle_control(q, registry_, *caps_.get()));
    j["engines"] = engines_;
    res.set_header("Cache-Control", "no-store");
    res.set_content(j.dump(), "application/json");
  });
  // ?after=N returns the first result with index > N, waiting up to wait_ms (long poll);
  // faces=ID: the viewer holds the faces of that X-Fq-Faces-Id (they are not sent again).
  s.Get(R"(/streams/([^/]+)/latest)", [this](const httplib::Request& req, httplib::Response& res) {
    const std::string stream = req.matches[1];
    StreamSettings unused;
    if (Status id = check_stream_id(stream, *caps_.get()); !id.ok()) {
      res.status = 404;
      res.set_content(id.message() + "\n", "text/plain");
      return;
    }
    if (!registry_.find(stream, unused)) {
      res.status = 404;
      res.set_content("unknown stream '" + printable_id(stream) + "'\n", "text/plain");
      return;
    }
    uint64_t after = 0, faces_id = 0;
    int wait_ms = 0;
    try {
      if (req.has_param("after")) after = std::stoull(req.get_param_value("after"));
      if (req.has_param("faces")) faces_id = std::stoull(req.get_param_value("faces"));
      if (req.has_param("wait_ms"))
        wait_ms = std::clamp(std::stoi(req.get_param_value("wait_ms")), 0, kMaxWaitMs);
    } catch (const std::exception&) {
      res.status = 400;
      res.set_content("after, faces and wait_ms must be whole numbers\n", "text/plain");
      return;
    }
    // A waiting poll holds its connection's thread: past http.max_long_polls it is refused
    // at once (the viewer asks again a second later) instead of taking more.
    LongPollTicket ticket(long_polls_, wait_ms > 0 ? config_.http.max_long_polls : UINT32_MAX);
    if (!ticket.admitted()) {
      refusals_.add(HttpRefusal::kTooManyLongPolls);
      res.status = 503;
      res.set_header("Retry-After", "1");
      res.set_content("too many long polls waiting (http.max_long_polls)\n", "text/plain");
      return;
    }
    auto r = latest_.wait_newer(stream, after, std::chrono::milliseconds(wait_ms));
    if (!r) {
      res.status = 204;  // nothing newer yet: the viewer asks again
      return;
    }
    send_latest(std::move(r), faces_id, res);
  });
}

void HttpServer::add_viewer_routes() {
  const std::filesystem::path root(config_.http.web_root);
  if (viewer_installed(root)) {
    server_->set_mount_point("/", root.string());
    // Module scripts need a JavaScript type, and WebAssembly streams only as application/wasm.
    // application/x-javascript (a JavaScript type to browsers) rather than text/javascript:
    // httplib compresses text/* on every request, and brotli at its default quality took
    // 4 s for three.core.js (1.4 MB) on the 2-core development machine.
    server_->set_file_extension_and_mimetype_mapping("js", "application/x-javascript");
    server_->set_file_extension_and_mimetype_mapping("wasm", "application/wasm");
    return;
  }
  spdlog::info("http: no viewer in {} (run scripts/web-deps.sh); / explains how to install it",
               root.string());
  const std::string message =
      "fqd is running, but its live viewer is not installed in " + root.string() +
      ".\nIn fq's source tree, install it with `bash scripts/web-deps.sh` (npm ci in web/), then run fqd "
      "from there or `cmake --install` again (it ships the viewer to <prefix>/share/fq/web, where fqd "
      "looks); "
      "or point [http] web_root at a folder that has it.\nThe API works without it: /metrics /healthz "
      "/streams "
      "/streams/ID/latest\n";
  server_->Get("/", [message](const httplib::Request&, httplib::Response& res) {
    res.status = 404;
    res.set_content(message, "text/plain");
  });
}

void HttpServer::warn_if_exposed(const std::string& host) const {
  const HttpConfig& h = config_.http;
  if (config_.security.enabled() && h.token_file.empty())
    spdlog::warn(
        "http: [security] is on but http.token_file is not set: /streams, the results and the viewer "
        "answer 403 (only /metrics and /healthz are served)");
  if (is_loopback_host(host)) return;
  if (h.tls_cert_file.empty())
    spdlog::warn(
        "http: {} is reachable from other hosts without TLS: requests, tokens and results travel in "
        "clear (set http.tls_cert_file and http.tls_key_file)",
        h.listen);
  if (h.token_file.empty() && !config_.security.enabled())
    spdlog::warn(
        "http: {} is reachable from other hosts without a token: anyone who can connect reads the "
        "metrics, the streams and their geometry (set http.token_file)",
        h.listen);
}

Status HttpServer::start() {
  std::string host;
  int port = 0;
  if (!split_host_port(config_.http.listen, host, port))
    return invalid_argument("http.listen \"" + config_.http.listen + "\" is not host:port");
  HttpAccessRules rules;
  FQ_RETURN_IF_ERROR(load_http_access(config_.http, config_.security.enabled(), rules));
  access_.set(std::move(rules));
  if (!config_.http.tls_cert_file.empty()) {
    FQ_RETURN_IF_ERROR(make_tls_context(config_.http.tls_cert_file, config_.http.tls_key_file, tls_));
    server_->set_tls(tls_.get());
  }
  server_->set_request_check([this](const httplib::Request& req, httplib::Response& res) {
    return access_.check(req, res, refusals_);
  });
  warn_if_exposed(host);
  add_api_routes();
  add_viewer_routes();
  port = server_->bind_listener(host, port);
  if (port < 0)
    return invalid_argument("cannot listen on http " + config_.http.listen + ": " + std::strerror(errno) +
                            " (another process on that port?)");
  url_ = std::string(tls_ ? "https" : "http") + "://" +
         (host.find(':') != std::string::npos ? "[" + host + "]" : host) + ":" + std::to_string(port);
  thread_ = std::thread([this] {
    server_->listen_after_bind();
    listen_returned_ = true;
  });
  // httplib's stop() only reaches a server that is already listening: wait until it is.
  while (!server_->is_running() && !listen_returned_)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  return {};
}

void HttpServer::stop() {
  if (!thread_.joinable()) return;
  latest_.close();  // long polls return at once
  server_->stop();  // no more connections
  thread_.join();
  server_->close_connections();  // the open ones end now, whatever their peers do
}

}  // namespace fq::daemon
