#include "daemon/http_front.h"

#include <sys/socket.h>
#include <unistd.h>

namespace fq::daemon {
namespace {

// Requests served on one connection before it is closed (the viewer polls on one connection).
constexpr int kRequestsPerConnection = 100;
// How long a request may take to send anything (and a response to make progress).
constexpr std::chrono::seconds kIoTimeout{5};
constexpr std::chrono::seconds kIdleTimeout{5};

// The stream of the connection this thread serves, for the pre-routing check (the library
// hands handlers the request, not the stream).
thread_local HttpStream* current_stream = nullptr;

bool has_body(const httplib::Request& req) {
  if (req.has_header("Transfer-Encoding")) return true;
  const std::string length = req.get_header_value("Content-Length");
  return !length.empty() && length.find_first_not_of('0') != std::string::npos;
}

// A peer still sending (a refused body) would get a reset instead of the answer if the socket
// were closed with unread bytes: stop writing, then read briefly what is left.
void close_gently(int fd) {
  ::shutdown(fd, SHUT_WR);
  char sink[4096];
  timeval tv{0, 100'000};
  setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  for (int i = 0; i < 16 && ::recv(fd, sink, sizeof sink, 0) > 0; ++i) {
  }
  ::close(fd);
}

}  // namespace

HttpFront::HttpFront(const HttpConfig& config, HttpRefusalCounters& refusals)
    : head_limits_{config.max_head_bytes, config.max_headers}, refusals_(refusals) {
  // SO_REUSEADDR only (a restart may bind while old connections linger): without the
  // library's SO_REUSEPORT a second process cannot bind the same port.
  set_socket_options([](int s) {
    int yes = 1;
    setsockopt(s, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
  set_payload_max_length(0);  // no route reads a body (pre_routing refuses them first)
  set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) { return pre_routing(req, res); });
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
  serve(sock);
  close_gently(sock);
  return true;
}

void HttpFront::serve(int fd) {
  HttpStream stream(fd, kIoTimeout);
  current_stream = &stream;
  for (int n = 1; n <= kRequestsPerConnection && stream.wait_for_request(kIdleTimeout); ++n) {
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
