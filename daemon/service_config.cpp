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

namespace {

// An array of non-empty strings; records an error on `r` otherwise.
void read_strings(TomlReader& r, const char* key, std::vector<std::string>& out) {
  const toml::node* n = r.raw(key);
  if (!n) return;
  const toml::array* a = n->as_array();
  std::vector<std::string> v;
  for (size_t i = 0; a && i < a->size(); ++i) {
    auto s = (*a)[i].value_exact<std::string>();
    if (!s || s->empty()) break;
    v.push_back(*s);
  }
  if (!a || v.size() != a->size()) return r.fail(key, "must be an array of non-empty strings");
  out = std::move(v);
}

}  // namespace

Status read_sub_ingest(TomlReader& root, SubIngestConfig& out) {
  const toml::table* t = root.table("ingest");
  if (!t) return {};
  TomlReader r(*t, root.source(), "ingest");
  read_strings(r, "connect", out.connect);
  read_strings(r, "streams", out.streams);
  for (const std::string& ep : out.connect)
    if (ep.find("://") == std::string::npos) r.fail("connect", "\"" + ep + "\" is not a ZeroMQ address like tcp://host:5555");
  if (!out.streams.empty() && out.connect.empty())
    r.fail("streams", "assigns streams of SUB ingest, but ingest.connect lists no producer");
  return r.finish();
}

Status read_service_sections(TomlReader& root, HttpConfig& http, StatsLogConfig& stats,
                             SubIngestConfig& sub_ingest) {
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
  if (Status s = read_sub_ingest(root, sub_ingest); !s.ok()) return s;
  if (const toml::table* t = root.table("stats")) {
    TomlReader r(*t, root.source(), "stats");
    r.read("interval_s", stats.interval_s, 0.0, 86400.0);
    if (Status s = r.finish(); !s.ok()) return s;
  }
  return {};
}

}  // namespace fq::daemon
