#include "daemon/http/http_stream.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <openssl/err.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <string>

namespace fq::daemon {
namespace {

using Clock = std::chrono::steady_clock;

void ip_and_port(const sockaddr_storage& a, std::string& ip, int& port) {
  char text[INET6_ADDRSTRLEN] = "";
  if (a.ss_family == AF_INET) {
    const auto& v4 = reinterpret_cast<const sockaddr_in&>(a);
    inet_ntop(AF_INET, &v4.sin_addr, text, sizeof text);
    port = ntohs(v4.sin_port);
  } else if (a.ss_family == AF_INET6) {
    const auto& v6 = reinterpret_cast<const sockaddr_in6&>(a);
    inet_ntop(AF_INET6, &v6.sin6_addr, text, sizeof text);
    port = ntohs(v6.sin6_port);
  }
  ip = text;
}

// The answer to a refused head, written by the stream itself (the library would say 400).
std::string refusal_response(HttpRefusal why, const HttpStream::HeadLimits& limits) {
  std::string status = "431 Request Header Fields Too Large", body;
  if (why == HttpRefusal::kTooManyHeaders) {
    body = "more than " + std::to_string(limits.max_headers) + " header lines (http.max_headers)\n";
  } else if (why == HttpRefusal::kHeadTimeout) {
    status = "408 Request Timeout";
    body = "request head not complete within http.request_timeout_s\n";
  } else {
    body = "request head over " + std::to_string(limits.max_bytes) + " bytes (http.max_head_bytes)\n";
  }
  return "HTTP/1.1 " + status + "\r\nConnection: close\r\nContent-Type: text/plain\r\nContent-Length: " +
         std::to_string(body.size()) + "\r\n\r\n" + body;
}

}  // namespace

HttpStream::HttpStream(int fd, SSL_CTX* tls, std::chrono::milliseconds io_timeout)
    : fd_(fd), io_timeout_(io_timeout) {
  fcntl(fd_, F_SETFL, fcntl(fd_, F_GETFL, 0) | O_NONBLOCK);
  if (tls && (ssl_ = SSL_new(tls))) SSL_set_fd(ssl_, fd_);
}

HttpStream::~HttpStream() {
  if (!ssl_) return;
  if (SSL_is_init_finished(ssl_)) SSL_shutdown(ssl_);  // close_notify, without waiting for the peer's
  SSL_free(ssl_);
}

bool HttpStream::handshake(std::chrono::milliseconds timeout) {
  if (!ssl_) return false;
  const auto deadline = Clock::now() + timeout;
  for (;;) {
    ERR_clear_error();
    const int r = SSL_accept(ssl_);
    if (r == 1) return true;
    const int e = SSL_get_error(ssl_, r);
    if (e != SSL_ERROR_WANT_READ && e != SSL_ERROR_WANT_WRITE) return false;
    if (!wait(e == SSL_ERROR_WANT_READ ? POLLIN : POLLOUT, deadline)) return false;
  }
}

ssize_t HttpStream::try_receive(char* ptr, size_t size, short& want) {
  want = POLLIN;
  if (!ssl_) {
    const ssize_t n = ::recv(fd_, ptr, size, 0);
    if (n >= 0) return n;
    return errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR ? -1 : -2;
  }
  ERR_clear_error();
  const int n = SSL_read(ssl_, ptr, static_cast<int>(std::min<size_t>(size, INT_MAX)));
  if (n > 0) return n;
  switch (SSL_get_error(ssl_, n)) {
    case SSL_ERROR_WANT_READ:
      return -1;
    case SSL_ERROR_WANT_WRITE:
      want = POLLOUT;
      return -1;
    case SSL_ERROR_ZERO_RETURN:
      return 0;
    case SSL_ERROR_SYSCALL:  // a peer that closed without close_notify: the end too
      return ERR_peek_error() == 0 ? 0 : -2;
    default:
      return -2;
  }
}

ssize_t HttpStream::try_send(const char* ptr, size_t size, short& want) {
  want = POLLOUT;
  if (!ssl_) {
    const ssize_t n = ::send(fd_, ptr, size, MSG_NOSIGNAL);
    if (n >= 0) return n;
    return errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR ? -1 : -2;
  }
  ERR_clear_error();
  const int n = SSL_write(ssl_, ptr, static_cast<int>(std::min<size_t>(size, INT_MAX)));
  if (n > 0) return n;
  const int e = SSL_get_error(ssl_, n);
  if (e == SSL_ERROR_WANT_READ) want = POLLIN;
  return e == SSL_ERROR_WANT_READ || e == SSL_ERROR_WANT_WRITE ? -1 : -2;
}

bool HttpStream::wait(short events, Clock::time_point deadline) const {
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    if (left < 0) return false;
    pollfd p{fd_, events, 0};
    const int n = ::poll(&p, 1, static_cast<int>(std::min<int64_t>(left, 60'000)));
    if (n > 0) return true;  // ready, or an error/hangup the next call reports
    if (n < 0 && errno != EINTR) return false;
  }
}

bool HttpStream::fill() {
  for (;;) {
    short want = POLLIN;
    const ssize_t n = try_receive(buf_, sizeof buf_, want);
    if (n > 0) {
      pos_ = 0;
      len_ = static_cast<size_t>(n);
      return true;
    }
    if (n == 0) {
      eof_ = true;
      return false;
    }
    if (n == -2) return false;
    if (!wait(want, in_head_ ? head_deadline_ : Clock::now() + io_timeout_)) {
      if (in_head_) refuse(HttpRefusal::kHeadTimeout);
      return false;
    }
  }
}

bool HttpStream::is_readable() const { return pos_ < len_ || wait(POLLIN, Clock::now() + io_timeout_); }

bool HttpStream::is_writable() const { return wait(POLLOUT, Clock::now() + io_timeout_); }

bool HttpStream::wait_for_request(std::chrono::milliseconds idle) {
  if (refusal_ || eof_) return false;
  if (pos_ < len_ || (ssl_ && SSL_pending(ssl_) > 0)) return true;  // a pipelined request is here
  return wait(POLLIN, Clock::now() + idle) && fill();
}

void HttpStream::begin_head(const HeadLimits& limits) {
  limits_ = limits;
  head_deadline_ = Clock::now() + limits.timeout;
  in_head_ = true;
  head_bytes_ = 0;
  head_lines_ = 0;
}

ssize_t HttpStream::refuse(HttpRefusal why) {
  refusal_ = why;
  const std::string answer = refusal_response(why, limits_);
  send_all(answer.data(), answer.size());
  discard_writes_ = true;
  return -1;
}

ssize_t HttpStream::read(char* ptr, size_t size) {
  if (refusal_) return -1;
  if (pos_ == len_ && !fill()) return eof_ ? 0 : -1;
  const size_t n = std::min(size, len_ - pos_);
  if (in_head_) {
    head_bytes_ += n;
    head_lines_ += static_cast<uint32_t>(std::count(buf_ + pos_, buf_ + pos_ + n, '\n'));
    if (head_bytes_ > limits_.max_bytes) return refuse(HttpRefusal::kHeadTooLarge);
    // Lines: the request line, the headers and the blank line that ends them.
    if (head_lines_ > limits_.max_headers + 2) return refuse(HttpRefusal::kTooManyHeaders);
  }
  std::copy_n(buf_ + pos_, n, ptr);
  pos_ += n;
  return static_cast<ssize_t>(n);
}

bool HttpStream::send_all(const char* ptr, size_t size) {
  for (size_t done = 0; done < size;) {
    short want = POLLOUT;
    const ssize_t n = try_send(ptr + done, size - done, want);
    if (n > 0)
      done += static_cast<size_t>(n);
    else if (n != -1 || !wait(want, Clock::now() + io_timeout_))
      return false;
  }
  return true;
}

ssize_t HttpStream::write(const char* ptr, size_t size) {
  if (discard_writes_) return static_cast<ssize_t>(size);
  return send_all(ptr, size) ? static_cast<ssize_t>(size) : -1;
}

void HttpStream::get_remote_ip_and_port(std::string& ip, int& port) const {
  sockaddr_storage a{};
  socklen_t len = sizeof a;
  if (getpeername(fd_, reinterpret_cast<sockaddr*>(&a), &len) == 0) ip_and_port(a, ip, port);
}

void HttpStream::get_local_ip_and_port(std::string& ip, int& port) const {
  sockaddr_storage a{};
  socklen_t len = sizeof a;
  if (getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &len) == 0) ip_and_port(a, ip, port);
}

}  // namespace fq::daemon
