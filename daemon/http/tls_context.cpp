#include "daemon/http/tls_context.h"

#include <openssl/err.h>

namespace fq::daemon {
namespace {

std::string openssl_reason() {
  const unsigned long e = ERR_get_error();
  ERR_clear_error();
  if (e == 0) return "unknown OpenSSL error";
  char text[256];
  ERR_error_string_n(e, text, sizeof text);
  return text;
}

}  // namespace

Status make_tls_context(const std::string& cert_file, const std::string& key_file, TlsContext& out) {
  TlsContext ctx(SSL_CTX_new(TLS_server_method()));
  if (!ctx) return invalid_argument("TLS: cannot make a context: " + openssl_reason());
  SSL_CTX_set_min_proto_version(ctx.get(), TLS1_2_VERSION);
  SSL_CTX_set_options(ctx.get(), SSL_OP_NO_COMPRESSION | SSL_OP_NO_RENEGOTIATION);
  // The stream writes from its own buffer, possibly again after SSL_ERROR_WANT_WRITE.
  SSL_CTX_set_mode(ctx.get(), SSL_MODE_ENABLE_PARTIAL_WRITE | SSL_MODE_ACCEPT_MOVING_WRITE_BUFFER);
  if (SSL_CTX_use_certificate_chain_file(ctx.get(), cert_file.c_str()) != 1)
    return invalid_argument("http.tls_cert_file " + cert_file + ": " + openssl_reason());
  if (SSL_CTX_use_PrivateKey_file(ctx.get(), key_file.c_str(), SSL_FILETYPE_PEM) != 1)
    return invalid_argument("http.tls_key_file " + key_file + ": " + openssl_reason());
  if (SSL_CTX_check_private_key(ctx.get()) != 1)
    return invalid_argument("http.tls_key_file " + key_file + " does not match http.tls_cert_file " +
                            cert_file);
  out = std::move(ctx);
  return {};
}

}  // namespace fq::daemon
