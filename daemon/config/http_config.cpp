#include "daemon/config/http_config.h"

#include <charconv>
#include <filesystem>

#include "daemon/config/toml_reader.h"

namespace fq::daemon {

bool split_host_port(const std::string& listen, std::string& host, int& port) {
  const size_t colon = listen.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == listen.size()) return false;
  host = listen.substr(0, colon);
  if (host.size() >= 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
  const char* first = listen.data() + colon + 1;
  const char* last = listen.data() + listen.size();
  auto [end, ec] = std::from_chars(first, last, port);
  return ec == std::errc() && end == last && port >= 0 && port <= 65535 && !host.empty();
}

namespace {

void read_web_root(TomlReader& r, const std::string& source, std::string& web_root) {
  const toml::node* n = r.raw("web_root");
  if (!n) return;
  const auto root_dir = n->value_exact<std::string>();
  if (!root_dir || root_dir->empty()) return r.fail("web_root", "must be a non-empty folder path");
  // Relative to the config file, so that a config finds its viewer from any directory.
  const std::filesystem::path p(*root_dir), file(source);
  web_root = p.is_relative() && std::filesystem::is_regular_file(file)
                 ? (file.parent_path() / p).lexically_normal().string()
                 : p.string();
}

}  // namespace

Status read_http_config(TomlReader& root, HttpConfig& http) {
  const toml::table* t = root.table("http");
  if (!t) return {};
  TomlReader r(*t, root.source(), "http");
  r.read("listen", http.listen);
  std::string host;
  int port = 0;
  if (!http.listen.empty() && !split_host_port(http.listen, host, port))
    r.fail("listen", "must be \"host:port\" like \"127.0.0.1:8080\" (or \"\" for no HTTP listener)");
  read_web_root(r, root.source(), http.web_root);
  // A head needs its request line and a Host line; 1 MiB is far above any browser's.
  r.read("max_head_bytes", http.max_head_bytes, 256, 1 << 20);
  r.read("max_headers", http.max_headers, 4, 1000);
  // Below FD_SETSIZE with room for fqd's other descriptors: the library refuses sockets past it.
  r.read("max_connections", http.max_connections, 1, 900);
  r.read("request_timeout_s", http.request_timeout_s, 0.1, 300.0);
  r.read("idle_timeout_s", http.idle_timeout_s, 0.1, 3600.0);
  r.read("max_long_polls", http.max_long_polls, 0, 900);
  r.read("token_file", http.token_file);
  r.read("tls_cert_file", http.tls_cert_file);
  r.read("tls_key_file", http.tls_key_file);
  if (http.tls_cert_file.empty() != http.tls_key_file.empty())
    r.fail(http.tls_cert_file.empty() ? "tls_key_file" : "tls_cert_file",
           "needs http.tls_cert_file and http.tls_key_file together");
  r.read("allowed_hosts", http.allowed_hosts);
  return r.finish();
}

}  // namespace fq::daemon
