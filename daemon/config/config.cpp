#include "daemon/config/config.h"

#include <algorithm>
#include <fstream>
#include <optional>
#include <sstream>
#include <thread>

#include "core/param_table.h"
#include "daemon/config/echo_value.h"
#include "daemon/config/stream_id.h"
#include "daemon/config/stream_setting_table.h"
#include "daemon/config/toml_reader.h"

namespace fq::daemon {
namespace {

constexpr int64_t kMaxThreads = 256;

// The TOML table of a parameter row: [filter] holds the filter's, "qf+"'s noise and the
// temporal strength, [cluster] the clustering's.
const char* toml_table(ParamGroup g) { return g == ParamGroup::kCluster ? "cluster" : "filter"; }

// One row of the parameter table from its key, if present; the reader records a bad value.
void read_row(TomlReader& r, const ParamRow& row, Params& p) {
  const char* key = row.toml_key();
  switch (row.kind) {
    case ParamKind::kFloat: {
      auto v = static_cast<float>(row.get(p));
      r.read(key, v);
      row.set(p, v);
      // The row's range checked here, where the reader knows the key's line. check_param's
      // message starts with the row's name; the reader puts the dotted key in its place.
      if (Status s = check_param(row, v); !s.ok() && r.raw(key)) {
        const std::string& m = s.message();
        const size_t name = std::string_view(row.name).size();
        r.fail(key, m.compare(0, name, row.name) == 0 ? m.substr(name + 1) : m);
      }
      return;
    }
    case ParamKind::kUint: {
      auto v = static_cast<uint32_t>(row.get(p));
      r.read(key, v, static_cast<int64_t>(row.lo), static_cast<int64_t>(row.hi));
      row.set(p, v);
      return;
    }
    case ParamKind::kBool: {
      bool v = row.get(p) != 0.0;
      r.read(key, v);
      row.set(p, v);
      return;
    }
    case ParamKind::kEnum: {
      std::string name = format_param(row, row.get(p));
      r.read(key, name);
      double v = 0;
      if (parse_param(row, name, v).ok())
        row.set(p, v);
      else
        r.fail(key, "must be " + choice_names(row, " or ", true) + " (got \"" + echo_value(name) + "\")");
      return;
    }
  }
}

// Every row of the parameter table that lives in TOML table `table` ("filter" or "cluster").
void read_params(TomlReader& r, std::string_view table, Params& p) {
  for (const ParamRow& row : param_table())
    if (row.on(kToml) && table == toml_table(row.group)) read_row(r, row, p);
}

// Reads a stream table ([defaults] or [streams.<id>]) over `s`.
Status read_stream(const toml::table& t, const std::string& source, const std::string& path,
                   StreamSettings& s) {
  TomlReader r(t, source, path);
  std::string compute = compute_name(s.params);
  r.read("compute", compute);
  if (!parse_compute(compute, s.params))
    r.fail("compute",
           "must be \"filter\", \"cluster\" or \"filter_and_cluster\" (got \"" + echo_value(compute) + "\")");
  read_settings(r, nullptr, s);
  struct Sub {
    const char* key;
    void (*fn)(TomlReader&, StreamSettings&);
  };
  const Sub subs[] = {
      {"filter", [](TomlReader& x, StreamSettings& st) { read_params(x, "filter", st.params); }},
      {"cluster", [](TomlReader& x, StreamSettings& st) { read_params(x, "cluster", st.params); }},
      {"output", [](TomlReader& x, StreamSettings& st) { read_settings(x, "output", st); }},
  };
  for (const Sub& sub : subs) {
    const toml::table* st = r.table(sub.key);
    if (!st) continue;
    TomlReader sr(*st, source, r.name(sub.key));
    sub.fn(sr, s);
    FQ_RETURN_IF_ERROR(sr.finish());
  }
  FQ_RETURN_IF_ERROR(r.finish());
  if (Status v = validate(s); !v.ok()) return invalid_argument(source + ": [" + path + "] " + v.message());
  return {};
}

Status read_endpoints(TomlReader& root, Endpoints& e) {
  const toml::table* t = root.table("endpoints");
  if (!t) return {};
  TomlReader r(*t, root.source(), "endpoints");
  r.read("ingest", e.ingest);
  r.read("publish", e.publish);
  r.read("control", e.control);
  // Their syntax is checked with the files the config names (config_check.h), every problem
  // at once. Ports * and 0 are picked by the system at bind time, so equal strings do not collide.
  auto fixed = [](const std::string& ep) { return !ep.ends_with(":*") && !ep.ends_with(":0"); };
  auto same = [&](const std::string& a, const std::string& b) { return a == b && fixed(a); };
  if (same(e.ingest, e.publish) || same(e.ingest, e.control))
    r.fail("ingest", "must differ from endpoints.publish and endpoints.control");
  else if (same(e.publish, e.control))
    r.fail("publish", "must differ from endpoints.control");
  return r.finish();
}

Status read_engine(TomlReader& root, EngineConfig& e) {
  const toml::table* t = root.table("engine");
  if (!t) return {};
  TomlReader r(*t, root.source(), "engine");
  std::string kind = engine_kind_name(e.kind);
  r.read("kind", kind);
  if (!parse_engine_kind(kind, e.kind))
    r.fail("kind", "must be \"auto\", \"cuda\", \"cpu\" or \"copy\" (got \"" + echo_value(kind) + "\")");
  r.read("gpus", e.gpus, 0, 63);
  r.read("cpu_alongside_gpus", e.cpu_alongside_gpus);
  r.read("cpu_threads", e.cpu_threads, 0, kMaxThreads);
  r.read("cpu_engines", e.cpu_engines, 1, 64);
  FQ_RETURN_IF_ERROR(r.finish());
  if (e.kind == EngineKind::kCuda && e.gpus.empty())
    return invalid_argument(root.source() +
                            ": engine.kind = \"cuda\" needs at least one entry in engine.gpus");
  return {};
}

Status read_sections(TomlReader& root, DaemonConfig& c) {
  FQ_RETURN_IF_ERROR(read_endpoints(root, c.endpoints));
  FQ_RETURN_IF_ERROR(read_engine(root, c.engine));
  if (const toml::table* t = root.table("threads")) {
    TomlReader r(*t, root.source(), "threads");
    r.read("decode", c.decode_threads, 0, kMaxThreads);
    r.read("encode", c.encode_threads, 0, kMaxThreads);
    FQ_RETURN_IF_ERROR(r.finish());
  }
  if (const toml::table* t = root.table("security")) {
    TomlReader r(*t, root.source(), "security");
    r.read("curve_key_file", c.security.curve_key_file);
    r.read("client_keys_file", c.security.client_keys_file);
    r.read("control_keys_file", c.security.control_keys_file);
    if (Status s = r.finish(); !s.ok()) return s;
  }
  if (const toml::table* t = root.table("caps")) {
    TomlReader r(*t, root.source(), "caps");
    r.read("max_vertices", c.caps.max_vertices, 3, 1ll << 31);
    r.read("max_frame_bytes", c.caps.max_frame_bytes, 64, 1ll << 40);
    r.read("max_streams", c.caps.max_streams, 1, 1 << 20);
    r.read("max_stream_id_bytes", c.caps.max_stream_id_bytes, 1, 4096);
    r.read("stream_idle_s", c.caps.stream_idle_s, 0.0, 1e9);
    r.read("metric_series_idle_s", c.caps.metric_series_idle_s, 0.0, 1e9);
    r.read("allowed_streams", c.caps.allowed_streams);
    r.read("max_neighbour_work", c.caps.max_neighbour_work, 1e3, 1e18);
    r.read("pool_idle_s", c.caps.pool_idle_s, 0.0, 1e9);
    r.read("engine_time_limit_s", c.caps.engine_time_limit_s, 0.0, 1e9);
    r.read("stop_grace_s", c.caps.stop_grace_s, 0.0, 3600.0);
    r.read("max_subscriber_results", c.caps.max_subscriber_results, 2, 1000);
    r.read("max_subscriptions", c.caps.max_subscriptions, 1, 100000);
    r.read("max_subscription_bytes", c.caps.max_subscription_bytes, 1, 1 << 24);
    r.read("max_queued_frames", c.caps.max_queued_frames, 1, 100000);
    r.read("max_queued_bytes", c.caps.max_queued_bytes, 1, 1ll << 40);
    r.read("memory_budget_mb", c.caps.memory_budget_mb, 0, 1ll << 24);
    FQ_RETURN_IF_ERROR(r.finish());
  }
  return {};
}

Status read_streams(TomlReader& root, DaemonConfig& c) {
  if (const toml::table* t = root.table("defaults")) {
    FQ_RETURN_IF_ERROR(read_stream(*t, root.source(), "defaults", c.defaults));
  }
  const toml::table* streams = root.table("streams");
  if (!streams) return {};
  const std::string count = std::to_string(streams->size());
  if (streams->size() > c.caps.max_streams)
    return invalid_argument(root.source() + ": " + count + " [streams.*] tables, over caps.max_streams = " +
                            std::to_string(c.caps.max_streams) + " (each is a stream fqd keeps)");
  for (const auto& [k, v] : *streams) {
    const std::string id(k.str());
    const std::string at = root.source() + ":" + std::to_string(v.source().begin.line) + ": ";
    // The ingest's own check: a table names a stream that a frame could make.
    if (Status s = validate_stream_id(id, c.caps.max_stream_id_bytes); !s.ok())
      return invalid_argument(at + "[streams.<id>]: " + s.message());
    const toml::table* st = v.as_table();
    if (!st) return invalid_argument(at + "streams." + echo_value(id) + " must be a table");
    StreamSettings s = c.defaults;
    FQ_RETURN_IF_ERROR(read_stream(*st, root.source(), "streams." + id, s));
    c.streams[id] = s;
  }
  return {};
}

// The line of every key and array item, by dotted name.
void record_lines(const toml::node& n, const std::string& name, std::map<std::string, int>& lines) {
  if (!name.empty()) lines[name] = static_cast<int>(n.source().begin.line);
  if (const toml::table* t = n.as_table()) {
    for (const auto& [k, v] : *t)
      record_lines(v, name.empty() ? std::string(k.str()) : name + "." + std::string(k.str()), lines);
  } else if (const toml::array* a = n.as_array()) {
    for (size_t i = 0; i < a->size(); ++i) record_lines((*a)[i], name + "[" + std::to_string(i) + "]", lines);
  }
}

}  // namespace

void DaemonConfig::resolve_auto_threads() {
  const int half = std::max(2, static_cast<int>(std::thread::hardware_concurrency() / 2));
  if (decode_threads == 0) decode_threads = half;
  if (encode_threads == 0) encode_threads = half;
}

const StreamSettings& DaemonConfig::settings_for(const std::string& stream_id) const {
  auto it = streams.find(stream_id);
  return it != streams.end() ? it->second : defaults;
}

std::string DaemonConfig::where(const std::string& key) const {
  if (source.empty()) return "built-in defaults";
  // A key the file does not set is placed at its table, where it would go.
  for (std::string k = key;; k.erase(k.rfind('.'))) {
    if (const auto it = lines.find(k); it != lines.end()) return source + ":" + std::to_string(it->second);
    if (k.find('.') == std::string::npos) return source;
  }
}

bool valid_log_level(const std::string& l) {
  for (const char* n : {"trace", "debug", "info", "warn", "error", "critical", "off"})
    if (l == n) return true;
  return false;
}

Status parse_config(std::string_view text, const std::string& source, DaemonConfig& out, bool allow_empty) {
  toml::table root_table;
  try {
    root_table = toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    return invalid_argument(source + ":" + std::to_string(e.source().begin.line) + ": " +
                            std::string(e.description()));
  }
  if (root_table.empty() && !allow_empty)
    return invalid_argument(source +
                            " has no settings: an empty file is refused (it would reset every stream to "
                            "the built-in defaults)");
  DaemonConfig c;
  TomlReader root(root_table, source, "");
  root.read("log_level", c.log_level);
  if (!valid_log_level(c.log_level))
    root.fail("log_level", "must be one of trace, debug, info, warn, error, critical, off");
  FQ_RETURN_IF_ERROR(read_sections(root, c));
  FQ_RETURN_IF_ERROR(read_streams(root, c));
  FQ_RETURN_IF_ERROR(read_service_sections(root, c.http, c.stats, c.sub_ingest));
  for (const std::string& id : c.sub_ingest.streams)
    if (Status s = validate_stream_id(id, c.caps.max_stream_id_bytes); !s.ok())
      return invalid_argument(source + ": ingest.streams: " + s.message());
  FQ_RETURN_IF_ERROR(root.finish());
  c.source = source;
  record_lines(root_table, "", c.lines);
  out = std::move(c);
  return {};
}

Status load_config(const std::string& path, DaemonConfig& out, bool allow_empty) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return invalid_argument("cannot open config file " + path);
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_config(ss.str(), path, out, allow_empty);
}

}  // namespace fq::daemon
