// One HTTP connection's bytes as cpp-httplib reads and writes them (an httplib::Stream), with
// fqd's bounds on every request's head.
//
// cpp-httplib 0.11 bounds neither the number of header lines nor the size of a request's head,
// and reads a header line whole before it checks the line's length (a 64 MiB run of "a:b"
// lines cost fqd 1.8 GB, kept). It has no option for either, so the bound sits here, under the
// parser: the library's line reader takes one byte per read(), so what read() hands out between
// begin_head() and end_head() is exactly the request line and the header lines. Past a limit
// read() fails before another byte is taken from the socket; the stream then answers 431 itself
// and swallows the answer the library writes for the failed read (a 400). A head that takes
// longer than its timeout (slowloris: a byte every few seconds) is answered 408 the same way.
// With a TLS context the bytes go through OpenSSL on the same non-blocking socket.
#pragma once

#include <httplib.h>
#include <openssl/ssl.h>

#include <chrono>
#include <cstdint>
#include <optional>

#include "daemon/http/http_refusals.h"

namespace fq::daemon {

class HttpStream final : public httplib::Stream {
 public:
  struct HeadLimits {
    uint32_t max_bytes = 16384;               ///< request line + header lines + the blank line
    uint32_t max_headers = 64;                ///< header lines
    std::chrono::milliseconds timeout{5000};  ///< the whole head, from its first byte
  };

  /// `fd`: a connected socket, made non-blocking here (the caller keeps and closes it);
  /// `tls`: null for plain HTTP, else the context to serve TLS with (handshake() first).
  /// A read or write that makes no progress for `io_timeout` fails.
  HttpStream(int fd, SSL_CTX* tls, std::chrono::milliseconds io_timeout);
  ~HttpStream() override;
  HttpStream(const HttpStream&) = delete;
  HttpStream& operator=(const HttpStream&) = delete;

  /// The TLS handshake, within `timeout`; false when it failed (nothing is sent then).
  bool handshake(std::chrono::milliseconds timeout);

  bool is_readable() const override;
  bool is_writable() const override;
  ssize_t read(char* ptr, size_t size) override;
  ssize_t write(const char* ptr, size_t size) override;
  void get_remote_ip_and_port(std::string& ip, int& port) const override;
  void get_local_ip_and_port(std::string& ip, int& port) const override;
  int socket() const override { return fd_; }

  /// Waits up to `idle` for the first byte of another request; false when none came, the
  /// peer closed or the stream failed.
  bool wait_for_request(std::chrono::milliseconds idle);
  /// Bounds the reads of the next request's head, until end_head().
  void begin_head(const HeadLimits& limits);
  void end_head() { in_head_ = false; }
  /// Why the last head was refused; nothing when it was not.
  std::optional<HttpRefusal> refusal() const { return refusal_; }
  /// Ends the connection once the current response is written (a refused request's unread
  /// body must not be taken for the next request).
  void close_after_response() { close_ = true; }
  bool closing() const { return close_ || refusal_.has_value(); }

 private:
  /// Reads more bytes into the buffer; false at the end, on an error or past the deadline.
  bool fill();
  /// One receive or send attempt: bytes moved (> 0), 0 at the end of the stream, -1 when it
  /// would block (`want`: the poll event to wait for), -2 on an error.
  ssize_t try_receive(char* ptr, size_t size, short& want);
  ssize_t try_send(const char* ptr, size_t size, short& want);
  /// Waits until the socket is ready for `events` (POLLIN/POLLOUT) or `deadline` passes.
  bool wait(short events, std::chrono::steady_clock::time_point deadline) const;
  ssize_t refuse(HttpRefusal why);
  bool send_all(const char* ptr, size_t size);

  int fd_;
  SSL* ssl_ = nullptr;
  std::chrono::milliseconds io_timeout_;
  char buf_[4096];
  size_t pos_ = 0, len_ = 0;
  bool eof_ = false;
  bool in_head_ = false;
  HeadLimits limits_;
  std::chrono::steady_clock::time_point head_deadline_;
  uint64_t head_bytes_ = 0;
  uint32_t head_lines_ = 0;
  std::optional<HttpRefusal> refusal_;
  bool discard_writes_ = false;  ///< after a refusal: the library's own answer is dropped
  bool close_ = false;
};

}  // namespace fq::daemon
