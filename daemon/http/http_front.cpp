#include "daemon/http/http_front.h"

#include <sys/socket.h>

namespace fq::daemon {
namespace {

// Requests served on one connection before it is closed (the viewer polls on one connection).
constexpr int kRequestsPerConnection = 100;

// The stream of the connection this thread serves, for the pre-routing check (the library
// hands handlers the request, not the stream).
thread_local HttpStream* current_stream = nullptr;

bool has_body(const httplib::Request& req) {
  if (req.has_header("Transfer-Encoding")) return true;
  const std::string length = req.get_header_value("Content-Length");
  return !length.empty() && length.find_first_not_of('0') != std::string::npos;
}

std::chrono::milliseconds ms(double seconds) {
  return std::chrono::milliseconds(static_cast<int64_t>(seconds * 1e3));
}

// Runs each task where it is queued. The library queues one task per accepted socket, and
// fqd's task (process_and_close_socket) only hands the socket to its connection thread, so
// the accept thread never waits on a peer and no queue of sockets can grow.
class InlineQueue : public httplib::TaskQueue {
 public:
  void enqueue(std::function<void()> fn) override { fn(); }
  void shutdown() override {}
};

}  // namespace

HttpFront::HttpFront(const HttpConfig& config, HttpRefusalCounters& refusals)
    : head_limits_{config.max_head_bytes, config.max_headers, ms(config.request_timeout_s)},
      io_timeout_(ms(config.request_timeout_s)),
      idle_timeout_(ms(config.idle_timeout_s)),
      refusals_(refusals),
      connections_(config.max_connections, refusals, [this](int fd) { serve(fd); }) {
  new_task_queue = [] { return new InlineQueue; };
  // SO_REUSEADDR only (a restart may bind while old connections linger): without the
  // library's SO_REUSEPORT a second process cannot bind the same port.
  set_socket_options([](int s) {
    int yes = 1;
    setsockopt(s, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
  set_payload_max_length(0);  // no route reads a body (pre_routing refuses them first)
  set_pre_routing_handler(
      [this](const httplib::Request& req, httplib::Response& res) { return pre_routing(req, res); });
}

HttpFront::~HttpFront() { close_connections(); }

void HttpFront::set_tls(SSL_CTX* tls) {
  tls_ = tls;
  connections_.set_answer_refusals(tls == nullptr);
}

int HttpFront::bind_listener(const std::string& host, int port) {
  if (port == 0) {
    port = bind_to_any_port(host);
    if (port <= 0) return -1;
  } else if (!bind_to_port(host, port)) {
    return -1;
  }
  // The library listens with a backlog of 5 (compiled into Debian's build): 200 clients
  // connecting at once waited 1 s and more for SYN retransmits. Linux takes a new backlog
  // from listen() on a socket that listens already.
  ::listen(svr_sock_, SOMAXCONN);
  return port;
}

HttpFront::HandlerResponse HttpFront::pre_routing(const httplib::Request& req, httplib::Response& res) {
  if (has_body(req)) {
    refusals_.add(HttpRefusal::kBody);
    if (current_stream) current_stream->close_after_response();
    res.status = 413;
    res.set_content("fqd takes no request bodies\n", "text/plain");
    return HandlerResponse::Handled;
  }
  return check_ ? check_(req, res) : HandlerResponse::Unhandled;
}

bool HttpFront::process_and_close_socket(int sock) {
  connections_.open(sock);
  return true;
}

bool HttpFront::handshake_allowed(const HttpStream& stream) {
  // Checked before the handshake, whose private-key operation is what a flood of connections costs.
  std::string peer;
  int port = 0;
  stream.get_remote_ip_and_port(peer, port);
  int retry_after_s = 0;
  if (tls_rate_.allow_now(peer, retry_after_s)) return true;
  refusals_.add(HttpRefusal::kTlsRate);
  tls_rate_log_.log(spdlog::level::warn, "http: TLS connection from {} refused: over {} handshakes a second",
                    peer, kTlsHandshakesPerSecond);
  return false;
}

void HttpFront::serve(int fd) {
  HttpStream stream(fd, tls_, io_timeout_);
  if (tls_ && !handshake_allowed(stream)) return;
  if (tls_ && !stream.handshake(io_timeout_)) {
    refusals_.add(HttpRefusal::kTls);
    return;
  }
  current_stream = &stream;
  for (int n = 1; n <= kRequestsPerConnection && stream.wait_for_request(idle_timeout_); ++n) {
    stream.begin_head(head_limits_);
    bool closed = false;
    const bool ok = process_request(stream, n == kRequestsPerConnection, closed,
                                    [&](httplib::Request&) { stream.end_head(); });
    if (const auto why = stream.refusal()) refusals_.add(*why);
    if (!ok || closed || stream.closing()) break;
  }
  current_stream = nullptr;
}

}  // namespace fq::daemon
