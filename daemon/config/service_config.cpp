#include "daemon/config/service_config.h"

#include "daemon/config/toml_reader.h"

namespace fq::daemon {
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
  if (!out.streams.empty() && out.connect.empty())
    r.fail("streams", "assigns streams of SUB ingest, but ingest.connect lists no producer");
  return r.finish();
}

Status read_service_sections(TomlReader& root, HttpConfig& http, StatsLogConfig& stats,
                             SubIngestConfig& sub_ingest) {
  if (Status s = read_http_config(root, http); !s.ok()) return s;
  if (Status s = read_sub_ingest(root, sub_ingest); !s.ok()) return s;
  if (const toml::table* t = root.table("stats")) {
    TomlReader r(*t, root.source(), "stats");
    r.read("interval_s", stats.interval_s, 0.0, 86400.0);
    if (Status s = r.finish(); !s.ok()) return s;
  }
  return {};
}

}  // namespace fq::daemon
