// The TLS server context of fqd's HTTP listener (OpenSSL, Debian libssl-dev): the certificate
// chain and private key of [http] tls_cert_file / tls_key_file, TLS 1.2 or newer.
//
// cpp-httplib's SSLServer would make the same context, but it serves each connection from the
// first byte on a pool thread with blocking reads (the pool slowloris exhausted); fqd serves
// connections itself (http_connections.h), so it runs OpenSSL's non-blocking handshake itself
// and only the context is made here.
#pragma once

#include <openssl/ssl.h>

#include <memory>
#include <string>

#include "common/status.h"

namespace fq::daemon {

struct SslCtxFree {
  void operator()(SSL_CTX* c) const { SSL_CTX_free(c); }
};
using TlsContext = std::unique_ptr<SSL_CTX, SslCtxFree>;

/// Loads the PEM certificate chain and key; an error names the file and OpenSSL's reason.
Status make_tls_context(const std::string& cert_file, const std::string& key_file, TlsContext& out);

}  // namespace fq::daemon
