#include "daemon/service/startup_report.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "common/version.h"

namespace fq::daemon {

std::string start_line(const ConfigSource& source, long pid) {
  const bool same = source.path.empty() || source.path == source.from;
  return fmt::format("{} starting, pid {}, configuration from {}{}", version_line("fqd"), pid, source.from,
                     same ? "" : " (" + source.path + ")");
}

std::vector<std::string> off_lines(const DaemonConfig& c) {
  std::vector<std::string> out;
  if (c.http.listen.empty())
    out.push_back(
        "fqd: HTTP off (http.listen is empty): no /metrics, /healthz, /streams or viewer; "
        "set http.listen or --http-listen 127.0.0.1:8080");
  if (!c.security.enabled())
    out.push_back(
        "fqd: security off (security.curve_key_file is empty): the ZeroMQ sockets are "
        "unencrypted and take any client");
  if (c.stats.interval_s <= 0)
    out.push_back(
        "fqd: [stats] lines off (stats.interval_s = 0): no periodic per-stream line, no late warnings");
  return out;
}

std::string cuda_line(const EngineConfig& engine, const std::vector<std::string>& names) {
  for (const std::string& n : names)
    if (n.rfind("cuda", 0) == 0) return "";
  if (!built_with_cuda())
    return "fqd: CUDA absent: this build has no CUDA engine, frames run on the CPU engine";
  if (engine.kind == EngineKind::kCpu || engine.kind == EngineKind::kCopy)
    return std::string("fqd: CUDA off: engine.kind = ") + engine_kind_name(engine.kind);
  return fmt::format(
      "fqd: CUDA absent: no GPU engine could be made on engine.gpus [{}], frames run on the CPU engine",
      fmt::join(engine.gpus, ", "));
}

}  // namespace fq::daemon
