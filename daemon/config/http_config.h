// [http]: fqd's HTTP listener, the bounds it holds for every request and connection, and who
// may use it. Read with the rest of the service sections (service_config.h).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "common/status.h"

namespace fq::daemon {

class TomlReader;

struct HttpConfig {
  /// "host:port" to listen on ("" = no HTTP listener; port 0 = any free port).
  std::string listen;
  /// Folder of the live viewer (index.html and its node_modules). A relative path in a config
  /// file is taken from that file's folder; the built-in default from the working directory.
  std::string web_root = "web";
  /// Bytes of one request's head (request line and header lines): past it the request is
  /// answered 431 and the connection closed, before more is read. fqd takes no request bodies:
  /// a request that announces one is answered 413 without reading it.
  uint32_t max_head_bytes = 16384;
  /// Header lines of one request (431 past it).
  uint32_t max_headers = 64;
  /// Connections open at once, each served on a thread of its own; more are answered 503.
  uint32_t max_connections = 256;
  /// A request's head must arrive within this from its first byte (else 408 and close), and a
  /// read or write that makes no progress for this long ends the connection.
  double request_timeout_s = 5.0;
  /// A kept-alive connection without a next request for this long is closed.
  double idle_timeout_s = 5.0;
  /// Long polls (/streams/ID/latest with wait_ms) waiting at once; more are answered 503 at
  /// once, so that viewers cannot hold every connection.
  uint32_t max_long_polls = 32;
  /// A file whose first line is the bearer token every request but /healthz must carry
  /// (http_access.h); "" = none.
  std::string token_file;
  /// PEM certificate chain and private key: both set, the listener speaks only HTTPS.
  std::string tls_cert_file, tls_key_file;
  /// Host header values (port ignored; "*.example.com" for a domain, "*" for any) accepted;
  /// empty: localhost, IP literals and the listen host (against DNS rebinding).
  std::vector<std::string> allowed_hosts;

  bool operator==(const HttpConfig&) const = default;
};

/// Splits "host:port" ("[::1]:8080" for IPv6); false when it is not of that form or the
/// port is outside 0..65535.
bool split_host_port(const std::string& listen, std::string& host, int& port);

/// Reads [http] from the root table (relative web_root taken from the file's folder).
Status read_http_config(TomlReader& root, HttpConfig& out);

}  // namespace fq::daemon
