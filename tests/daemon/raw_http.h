// HTTP on a plain TCP socket, for tests that must send what a well-behaved client would not
// (huge heads, bodies, connections that stay silent): every byte is the test's own.
#pragma once

#include <chrono>
#include <string>

#include "common/non_copyable.h"

namespace fq::test {

/// The port of "http://host:port" (0 when there is none).
int http_port(const std::string& url);

class RawConnection : NonCopyable {
 public:
  /// Connects to 127.0.0.1:`port` (ok() says whether it worked).
  explicit RawConnection(int port);
  ~RawConnection();
  bool ok() const { return fd_ >= 0; }
  /// Sends everything; false once the peer has closed or reset the connection.
  bool send(const std::string& bytes);
  /// Reads until the peer closes or `wait` passes without a byte; what came.
  std::string receive(std::chrono::milliseconds wait = std::chrono::seconds(10));
  /// True when the peer closed (or reset) the connection within `wait`.
  bool closed_by_peer(std::chrono::milliseconds wait);

 private:
  int fd_ = -1;
};

/// The status code of a raw response ("HTTP/1.1 431 ..." gives 431); 0 when there is none.
int status_of(const std::string& response);

/// One GET on a fresh connection: the status code, 0 when none came within `wait`.
int get_status(int port, const std::string& path, std::chrono::milliseconds wait = std::chrono::seconds(10),
               const std::string& extra_headers = "");

}  // namespace fq::test
