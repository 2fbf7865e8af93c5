#include "daemon/http/http_connections.h"

#include <poll.h>
#include <pthread.h>
#include <sys/select.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <string>
#include <system_error>
#include <thread>

namespace fq::daemon {
namespace {

// A peer still sending (a refused body, an unread pipelined request) would get a reset
// instead of the answer if the socket were closed with unread bytes: stop writing, then read
// for at most 100 ms and 64 KiB what is left.
void close_gently(int fd) {
  ::shutdown(fd, SHUT_WR);
  const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(100);
  char sink[4096];
  for (int i = 0; i < 16; ++i) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(until - std::chrono::steady_clock::now());
    pollfd p{fd, POLLIN, 0};
    if (left.count() <= 0 || ::poll(&p, 1, static_cast<int>(left.count())) <= 0) break;
    if (::recv(fd, sink, sizeof sink, MSG_DONTWAIT) <= 0) break;
  }
  ::close(fd);
}

const std::string& busy_response() {
  static const std::string body = "fqd: too many connections (http.max_connections)\n";
  static const std::string response =
      "HTTP/1.1 503 Service Unavailable\r\nConnection: close\r\nRetry-After: 1\r\nContent-Type: "
      "text/plain\r\n"
      "Content-Length: " +
      std::to_string(body.size()) + "\r\n\r\n" + body;
  return response;
}

std::string plain_response(const char* status, const std::string& body) {
  return std::string("HTTP/1.1 ") + status +
         "\r\nConnection: close\r\nContent-Type: text/plain\r\nContent-Length: " +
         std::to_string(body.size()) + "\r\n\r\n" + body;
}

/// The request line (up to its CR LF) read within `ms`, at most 1 KiB; empty on a timeout.
std::string request_line(int fd, int ms) {
  std::string line;
  const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(ms);
  char buf[256];
  while (line.size() < 1024 && line.find("\r\n") == std::string::npos) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(until - std::chrono::steady_clock::now());
    pollfd p{fd, POLLIN, 0};
    if (left.count() <= 0 || ::poll(&p, 1, static_cast<int>(left.count())) <= 0) return {};
    const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
    if (n <= 0) return {};
    line.append(buf, size_t(n));
  }
  return line.substr(0, line.find("\r\n"));
}

}  // namespace

HttpConnections::HttpConnections(uint32_t max_connections, HttpRefusalCounters& refusals,
                                 std::function<void(int)> serve)
    : max_connections_(max_connections), refusals_(refusals), serve_(std::move(serve)) {}

HttpConnections::~HttpConnections() { close_all(); }

size_t HttpConnections::open_count() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return open_.size();
}

void HttpConnections::refuse(int fd) {
  refusals_.add(HttpRefusal::kTooManyConnections);
  // Best effort and without waiting: the accept thread must not block on a peer.
  const std::string& busy = busy_response();
  if (answer_refusals_) (void)::send(fd, busy.data(), busy.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
  ::close(fd);
}

void HttpConnections::open(int fd) {
  bool lane = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    // The library checks sockets against FD_SETSIZE (select) and answers 500 past it.
    if (closing_ || fd >= FD_SETSIZE) {
      refuse(fd);
      return;
    }
    if (open_.size() >= max_connections_) {
      if (!healthy_ || !answer_refusals_ || lane_ >= kHealthLane) {
        refuse(fd);
        return;
      }
      lane = true;
      ++lane_;
    }
    open_.insert(fd);
    ++threads_;
  }
  try {
    std::thread([this, fd, lane] { lane ? answer_on_lane(fd) : run(fd); }).detach();
  } catch (const std::system_error&) {  // no thread to be had: the connection is refused
    std::lock_guard<std::mutex> lock(mutex_);
    open_.erase(fd);
    --threads_;
    if (lane) --lane_;
    refuse(fd);
  }
}

void HttpConnections::answer_on_lane(int fd) {
  const std::string line = request_line(fd, kHealthLaneHeadMs);
  const bool probe = line.rfind("GET /healthz ", 0) == 0 || line.rfind("GET /healthz?", 0) == 0;
  if (probe) {
    const std::string answer = healthy_() ? plain_response("200 OK", "ok\n")
                                          : plain_response("503 Service Unavailable", "not ready\n");
    (void)::send(fd, answer.data(), answer.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
  } else {
    refusals_.add(HttpRefusal::kTooManyConnections);
    const std::string& busy = busy_response();
    (void)::send(fd, busy.data(), busy.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    open_.erase(fd);
  }
  close_gently(fd);
  std::lock_guard<std::mutex> lock(mutex_);
  --lane_;
  --threads_;
  finished_.notify_all();
}

void HttpConnections::run(int fd) {
  // A write to a peer that reset raises SIGPIPE unless blocked (OpenSSL writes with write()):
  // blocked on this thread, it stays pending here and is discarded when the thread ends.
  sigset_t pipe;
  sigemptyset(&pipe);
  sigaddset(&pipe, SIGPIPE);
  pthread_sigmask(SIG_BLOCK, &pipe, nullptr);
  serve_(fd);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    open_.erase(fd);  // before the close: close_all must not shut down a reused number
  }
  close_gently(fd);
  std::lock_guard<std::mutex> lock(mutex_);
  --threads_;
  finished_.notify_all();
}

void HttpConnections::close_all() {
  std::unique_lock<std::mutex> lock(mutex_);
  closing_ = true;
  for (int fd : open_) ::shutdown(fd, SHUT_RDWR);
  finished_.wait(lock, [&] { return threads_ == 0; });
}

}  // namespace fq::daemon
