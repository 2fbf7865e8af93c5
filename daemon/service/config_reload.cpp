#include "daemon/service/config_reload.h"

#include <functional>

namespace fq::daemon {
namespace {

struct Setting {
  const char* name;
  std::function<bool(const DaemonConfig&, const DaemonConfig&)> same;
};

template <class Get>
Setting field(const char* name, Get get) {
  return {name, [get](const DaemonConfig& a, const DaemonConfig& b) { return get(a) == get(b); }};
}

// Each is fixed where it is used at start: a socket option, a bound, a thread count, a file
// opened once.
const std::vector<Setting>& restart_only() {
  using C = const DaemonConfig&;
  static const std::vector<Setting> settings = {
      field("endpoints.ingest", [](C c) { return c.endpoints.ingest; }),
      field("endpoints.publish", [](C c) { return c.endpoints.publish; }),
      field("endpoints.control", [](C c) { return c.endpoints.control; }),
      field("engine.kind", [](C c) { return c.engine.kind; }),
      field("engine.gpus", [](C c) { return c.engine.gpus; }),
      field("engine.cpu_alongside_gpus", [](C c) { return c.engine.cpu_alongside_gpus; }),
      field("engine.cpu_threads", [](C c) { return c.engine.cpu_threads; }),
      field("engine.cpu_engines", [](C c) { return c.engine.cpu_engines; }),
      field("threads.decode", [](C c) { return c.decode_threads; }),
      field("threads.encode", [](C c) { return c.encode_threads; }),
      field("caps.max_frame_bytes", [](C c) { return c.caps.max_frame_bytes; }),
      field("caps.max_streams", [](C c) { return c.caps.max_streams; }),
      field("caps.max_stream_id_bytes", [](C c) { return c.caps.max_stream_id_bytes; }),
      field("caps.max_subscriber_results", [](C c) { return c.caps.max_subscriber_results; }),
      field("caps.max_subscriptions", [](C c) { return c.caps.max_subscriptions; }),
      field("caps.max_subscription_bytes", [](C c) { return c.caps.max_subscription_bytes; }),
      field("security.curve_key_file", [](C c) { return c.security.curve_key_file; }),
      // Whether the control socket has its own list is its ZAP domain, set before bind; the
      // keys either list holds reload live.
      field("security.control_keys_file", [](C c) { return c.security.control_keys_file.empty(); }),
      field("http.listen", [](C c) { return c.http.listen; }),
      field("http.web_root", [](C c) { return c.http.web_root; }),
      field("http.max_head_bytes", [](C c) { return c.http.max_head_bytes; }),
      field("http.max_headers", [](C c) { return c.http.max_headers; }),
      field("http.max_connections", [](C c) { return c.http.max_connections; }),
      field("http.request_timeout_s", [](C c) { return c.http.request_timeout_s; }),
      field("http.idle_timeout_s", [](C c) { return c.http.idle_timeout_s; }),
      field("http.max_long_polls", [](C c) { return c.http.max_long_polls; }),
      field("http.tls_cert_file", [](C c) { return c.http.tls_cert_file; }),
      field("http.tls_key_file", [](C c) { return c.http.tls_key_file; }),
      field("stats.interval_s", [](C c) { return c.stats.interval_s; }),
      field("ingest.connect", [](C c) { return c.sub_ingest.connect; }),
      field("ingest.streams", [](C c) { return c.sub_ingest.streams; }),
  };
  return settings;
}

}  // namespace

std::vector<std::string> restart_only_changes(const DaemonConfig& running, DaemonConfig fresh) {
  fresh.resolve_auto_threads();
  std::vector<std::string> changed;
  for (const Setting& s : restart_only())
    if (!s.same(running, fresh)) changed.emplace_back(s.name);
  return changed;
}

}  // namespace fq::daemon
