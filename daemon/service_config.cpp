#include "daemon/service_config.h"

#include <charconv>
#include <filesystem>

#include "daemon/toml_reader.h"

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

Status read_service_sections(TomlReader& root, HttpConfig& http, StatsLogConfig& stats) {
  if (const toml::table* t = root.table("http")) {
    TomlReader r(*t, root.source(), "http");
    r.read("listen", http.listen);
    std::string host;
    int port = 0;
    if (!http.listen.empty() && !split_host_port(http.listen, host, port))
      r.fail("listen", "must be \"host:port\" like \"127.0.0.1:8080\" (or \"\" for no HTTP listener)");
    if (const toml::node* n = r.raw("web_root")) {
      const auto root_dir = n->value_exact<std::string>();
      if (!root_dir || root_dir->empty()) {
        r.fail("web_root", "must be a non-empty folder path");
      } else {
        // Relative to the config file, so that a config finds its viewer from any directory.
        const std::filesystem::path p(*root_dir), file(root.source());
        http.web_root = p.is_relative() && std::filesystem::is_regular_file(file)
                            ? (file.parent_path() / p).lexically_normal().string()
                            : p.string();
      }
    }
    if (Status s = r.finish(); !s.ok()) return s;
  }
  if (const toml::table* t = root.table("stats")) {
    TomlReader r(*t, root.source(), "stats");
    r.read("interval_s", stats.interval_s, 0.0, 86400.0);
    if (Status s = r.finish(); !s.ok()) return s;
  }
  return {};
}

}  // namespace fq::daemon
