#include "daemon/service/command_line.h"

#include <CLI/CLI.hpp>

#include "common/version.h"
#include "daemon/service/stream_shard.h"

namespace fq::daemon {

std::optional<int> parse_command_line(int argc, char** argv, CommandLine& out) {
  CLI::App app{"fqd: filters and clusters streamed mesh frames within a latency budget"};
  app.set_version_flag("--version", version_line("fqd"));
  app.add_option(
      "-c,--config", out.config_path,
      "TOML configuration file (default: $FQ_CONFIG, else /etc/fq/fqd.toml, else built-in defaults)");
  app.add_option("--log-level", out.log_level,
                 "override log_level: trace, debug, info, warn, error, critical, off")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "critical", "off"}));
  app.add_option("--log-format", out.log_format,
                 "text (default) or json: one JSON object a line, for log collectors")
      ->check(CLI::IsMember({"text", "json"}));
  app.add_option("--engine", out.engine,
                 "override engine.kind: auto, cuda, cpu or copy (returns its input: measures the host path)")
      ->check(CLI::IsMember({"auto", "cuda", "cpu", "copy"}));
  app.add_option("--http-listen", out.http_listen,
                 "override http.listen: HOST:PORT (port 0: any free port), or \"\" for no HTTP listener");
  app.add_option("--shard", out.shard,
                 "serve shard K of N of [ingest] streams (K/N; K may be a pod name ending in -K): "
                 "the ids whose FNV-1a hash modulo N is K");
  app.add_option("--shard-map", out.shard_map,
                 "print the shard of N that serves each [ingest] stream, and exit")
      ->check(CLI::Range(1, 1 << 16));
  app.add_flag("--print-endpoints", out.print_endpoints,
               "print the bound endpoints as one JSON line on stdout once listening (for ports given as *)");
  app.add_option("--endpoints-file", out.endpoints_file,
                 "also write that JSON line to this file once listening");
  app.add_flag("--check-config", out.check_only,
               "validate the configuration (with the flags applied) and exit");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // CLI11's own codes (109 for an unexpected argument, 105 for a bad value...) are not
    // what a service manager expects; every usage error is 2, help and version 0.
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  return std::nullopt;
}

Status apply_command_line(const CommandLine& cl, DaemonConfig& config,
                          std::vector<std::string>* shard_streams) {
  if (cl.log_level) config.log_level = *cl.log_level;
  if (cl.engine && !parse_engine_kind(*cl.engine, config.engine.kind))
    return invalid_argument("--engine must be auto, cuda, cpu or copy (got \"" + *cl.engine + "\")");
  if (config.engine.kind == EngineKind::kCuda && config.engine.gpus.empty())
    return invalid_argument("--engine cuda needs at least one entry in engine.gpus");
  if (cl.http_listen) {
    std::string host;
    int port = 0;
    if (!cl.http_listen->empty() && !split_host_port(*cl.http_listen, host, port))
      return invalid_argument(
          "--http-listen must be HOST:PORT like 127.0.0.1:8080, or \"\" for none (got \"" + *cl.http_listen +
          "\")");
    config.http.listen = *cl.http_listen;
  }
  if (cl.shard) {
    uint32_t index = 0, count = 0;
    FQ_RETURN_IF_ERROR(parse_shard(*cl.shard, index, count));
    if (config.sub_ingest.streams.empty())
      return invalid_argument("--shard needs the stream ids to spread in [ingest] streams");
    std::vector<std::string> kept = keep_shard(config.sub_ingest, index, count);
    if (shard_streams) *shard_streams = std::move(kept);
  }
  return {};
}

}  // namespace fq::daemon
