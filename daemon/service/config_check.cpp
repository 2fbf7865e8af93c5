#include "daemon/service/config_check.h"

#include <dirent.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <utility>

#include "common/curve_keys.h"
#include "daemon/http/http_access.h"
#include "daemon/http/tls_context.h"
#include "daemon/service/credentials.h"
#include "daemon/service/zmq_endpoint.h"

namespace fq::daemon {
namespace {

class Problems {
 public:
  explicit Problems(const DaemonConfig& c) : config_(c) {}

  /// `where: key value: what` (without the value when empty); `line_key` finds the line when
  /// it is not `key` (an array's item).
  void add(const std::string& key, const std::string& value, const std::string& what,
           const std::string& line_key = "") {
    lines_.push_back(config_.where(line_key.empty() ? key : line_key) + ": " + key +
                     (value.empty() ? "" : " " + value) + ": " + what);
  }

  /// `where: message` for a message that names the key itself.
  void note(const std::string& key, const std::string& message) {
    lines_.push_back(config_.where(key) + ": " + message);
  }

  /// True when `path` opens for reading as a file; otherwise a problem of `key`.
  bool readable(const std::string& key, const std::string& path) {
    if (const std::string why = credential_problem(path); !why.empty()) return add(key, path, why), false;
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return add(key, path, std::string("cannot be read: ") + std::strerror(errno)), false;
    struct stat st {};
    const bool folder = ::fstat(fd, &st) == 0 && S_ISDIR(st.st_mode);
    ::close(fd);
    if (folder) add(key, path, "is a folder, not a file");
    return !folder;
  }

  std::vector<std::string> take() { return std::move(lines_); }

 private:
  const DaemonConfig& config_;
  std::vector<std::string> lines_;
};

void check_endpoints(const DaemonConfig& c, Problems& p) {
  const std::pair<const char*, const std::string&> bound[] = {{"endpoints.ingest", c.endpoints.ingest},
                                                              {"endpoints.publish", c.endpoints.publish},
                                                              {"endpoints.control", c.endpoints.control}};
  for (const auto& [key, endpoint] : bound)
    if (const std::string why = endpoint_problem(endpoint, EndpointUse::kBind); !why.empty())
      p.add(key, endpoint, why);
  for (size_t i = 0; i < c.sub_ingest.connect.size(); ++i) {
    const std::string& endpoint = c.sub_ingest.connect[i];
    if (const std::string why = endpoint_problem(endpoint, EndpointUse::kConnect); !why.empty())
      p.add("ingest.connect", endpoint, why, "ingest.connect[" + std::to_string(i) + "]");
  }
}

// As Daemon::make_sockets reads them (load_curve_server_keys), every problem named.
void check_security(const SecurityConfig& s, Problems& p) {
  if (!s.curve_key_file.empty() && p.readable("security.curve_key_file", s.curve_key_file)) {
    CurveKeyPair pair;
    if (Status st = read_curve_key_file(s.curve_key_file, true, pair); !st.ok())
      p.add("security.curve_key_file", "", st.message());
  }
  if (s.enabled() && s.client_keys_file.empty())
    p.add("security.client_keys_file", "",
          "is not set: with CURVE on, only the client keys it lists may connect");
  if (!s.client_keys_file.empty() && p.readable("security.client_keys_file", s.client_keys_file)) {
    std::vector<std::string> keys;
    if (Status st = read_public_keys(s.client_keys_file, keys); !st.ok())
      p.add("security.client_keys_file", "", st.message());
    else if (keys.empty() && s.enabled())
      p.add("security.client_keys_file", s.client_keys_file, "lists no client key: no client could connect");
  }
  if (!s.control_keys_file.empty() && !s.enabled())
    p.add("security.control_keys_file", "",
          "is set but security.curve_key_file is not: it applies to CURVE only");
  if (s.enabled() && !s.control_keys_file.empty() &&
      p.readable("security.control_keys_file", s.control_keys_file)) {
    std::vector<std::string> keys;
    if (Status st = read_public_keys(s.control_keys_file, keys); !st.ok())
      p.add("security.control_keys_file", "", st.message());
    else if (keys.empty())
      p.add("security.control_keys_file", s.control_keys_file,
            "lists no client key: no client could reach the control socket");
  }
}

// As HttpServer::start reads them (load_http_access, make_tls_context). The default viewer
// folder may be missing (fqd then serves how to install it at /); one the file names may not.
void check_http(const DaemonConfig& c, Problems& p) {
  const HttpConfig& h = c.http;
  if (!h.token_file.empty() && p.readable("http.token_file", h.token_file)) {
    std::string token;
    if (Status st = read_http_token(h.token_file, token); !st.ok())
      p.add("http.token_file", h.token_file, st.message());
  }
  const bool cert = !h.tls_cert_file.empty() && p.readable("http.tls_cert_file", h.tls_cert_file);
  const bool key = !h.tls_key_file.empty() && p.readable("http.tls_key_file", h.tls_key_file);
  if (cert && key) {
    TlsContext tls;
    if (Status st = make_tls_context(h.tls_cert_file, h.tls_key_file, tls); !st.ok())
      p.note("http.tls_cert_file", st.message());  // names the file it is about
  }
  if (c.lines.count("http.web_root")) {
    if (DIR* folder = ::opendir(h.web_root.c_str()))
      ::closedir(folder);
    else
      p.add("http.web_root", h.web_root,
            std::string("cannot be opened as a folder: ") + std::strerror(errno));
  }
}

}  // namespace

std::vector<std::string> config_problems(const DaemonConfig& config) {
  Problems p(config);
  check_endpoints(config, p);
  check_security(config.security, p);
  check_http(config, p);
  return p.take();
}

}  // namespace fq::daemon
