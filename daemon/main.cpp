// fqd: the streaming daemon. Usage: fqd [--config configs/fqd.toml] [--engine cpu] ...
// Configuration: --config, else $FQ_CONFIG, else /etc/fq/fqd.toml, else built-in defaults;
// the flags override the file (daemon/service/command_line.h). Exit status: 0 after a stop signal,
// 1 when it cannot start (a port in use, a GPU missing), 2 for a usage error or an invalid
// configuration (a file or endpoint it names included: daemon/service/config_check.h).
// SIGINT/SIGTERM stop it (frames in flight are finished); SIGHUP reloads the file, the flags
// over it again (what a reload may change: daemon/service/config_reload.h).
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>

#include "common/tool_main.h"
#include "daemon/config/config.h"
#include "daemon/daemon.h"
#include "daemon/http/web_root.h"
#include "daemon/service/command_line.h"
#include "daemon/service/config_check.h"
#include "daemon/service/config_lookup.h"
#include "daemon/service/credentials.h"
#include "daemon/service/log_format.h"
#include "daemon/service/service_notify.h"
#include "daemon/service/signals.h"
#include "daemon/service/startup_report.h"
#include "daemon/service/stream_shard.h"

namespace {

std::string endpoints_json(const fq::daemon::BoundEndpoints& e) {
  nlohmann::json j{{"ingest", e.ingest}, {"publish", e.publish}, {"control", e.control}};
  if (!e.http.empty()) j["http"] = e.http;
  return j.dump();
}

// The file (or the built-in defaults), then the flags over it.
// `allow_empty`: false for a reload (parse_config says why).
fq::Status load(const fq::daemon::ConfigSource& source, const fq::daemon::CommandLine& cl,
                fq::daemon::DaemonConfig& config, std::vector<std::string>* shard_streams = nullptr,
                bool allow_empty = true) {
  if (!source.path.empty()) FQ_RETURN_IF_ERROR(fq::daemon::load_config(source.path, config, allow_empty));
  fq::daemon::resolve_default_web_root(config.http);
  FQ_RETURN_IF_ERROR(fq::daemon::apply_command_line(cl, config, shard_streams));
  // `credential:NAME` values: files systemd's LoadCredential= put there (daemon/service/credentials.h).
  fq::daemon::resolve_credentials(config, std::getenv("CREDENTIALS_DIRECTORY"));
  return {};
}

// Start and --check-config alike: every endpoint and file the configuration names, checked
// (config_check.h). False after one line on stderr per problem.
bool startable(const fq::daemon::DaemonConfig& config) {
  const std::vector<std::string> problems = fq::daemon::config_problems(config);
  for (const std::string& p : problems) std::fprintf(stderr, "fqd: invalid configuration: %s\n", p.c_str());
  return problems.empty();
}

// SIGHUP: the file again (the flags over it, as at start), applied whole or not at all: an
// invalid or empty file, or one that changes a setting only a restart can change, changes nothing.
void reload(const fq::daemon::ConfigSource& source, const fq::daemon::CommandLine& cl,
            fq::daemon::Daemon& daemon) {
  if (source.path.empty()) {
    spdlog::info("fqd: SIGHUP ignored: running on built-in defaults, no configuration file to reload");
    return;
  }
  fq::daemon::notify_service_manager("RELOADING=1");
  fq::daemon::DaemonConfig fresh;
  fq::Status s = load(source, cl, fresh, nullptr, /*allow_empty=*/false);
  if (s.ok()) s = daemon.reload(fresh);
  if (!s.ok())
    spdlog::error("fqd: SIGHUP: {} not reloaded, settings unchanged: {}", source.path, s.message());
  else
    spdlog::info("fqd: SIGHUP: reloaded {} (streams, caps, client keys, HTTP access, log level)",
                 source.path);
  fq::daemon::notify_service_manager("READY=1");
}

// --shard-map N: which of N shards serves each [ingest] stream.
int print_shard_map(const fq::daemon::DaemonConfig& config, int shards) {
  if (config.sub_ingest.streams.empty()) {
    std::fprintf(stderr, "fqd: --shard-map needs the stream ids to spread in [ingest] streams\n");
    return 2;
  }
  for (const std::string& id : config.sub_ingest.streams)
    std::printf("%s %u\n", id.c_str(), fq::daemon::shard_of(id, static_cast<uint32_t>(shards)));
  return 0;
}

void log_start(const fq::daemon::ConfigSource& source, const fq::daemon::DaemonConfig& config,
               const fq::daemon::CommandLine& cl, const std::vector<std::string>& shard_streams) {
  spdlog::info("{}", fq::daemon::start_line(source, static_cast<long>(getpid())));
  if (cl.shard)
    spdlog::info("fqd: shard {}: serves [{}] of [ingest] streams", *cl.shard, fmt::join(shard_streams, ", "));
  for (const std::string& line : fq::daemon::off_lines(config)) spdlog::info("{}", line);
}

int run(int argc, char** argv) {
  fq::daemon::CommandLine cl;
  if (std::optional<int> exit_status = fq::daemon::parse_command_line(argc, argv, cl)) return *exit_status;
  // Logs go to stderr: stdout carries only the --print-endpoints line.
  fq::daemon::use_log_format(cl.log_format);

  const fq::daemon::ConfigSource source = fq::daemon::find_config(cl.config_path, std::getenv("FQ_CONFIG"));
  fq::daemon::DaemonConfig config;
  std::vector<std::string> shard_streams;
  if (fq::Status s = load(source, cl, config, &shard_streams); !s.ok()) {
    std::fprintf(stderr, "fqd: invalid configuration: %s\n", s.message().c_str());
    return 2;
  }
  if (cl.shard_map > 0) return print_shard_map(config, cl.shard_map);  // reads no file the config names
  if (!startable(config)) return 2;
  if (cl.check_only) {
    std::printf("%s: configuration is valid\n",
                source.path.empty() ? source.from.c_str() : source.path.c_str());
    return 0;
  }
  spdlog::set_level(spdlog::level::from_str(config.log_level));
  log_start(source, config, cl, shard_streams);

  fq::daemon::block_stop_signals();  // before any thread exists, so all of them inherit it
  fq::daemon::Daemon daemon(config);
  if (fq::Status s = daemon.start(); !s.ok()) {
    spdlog::critical("fqd: cannot start: {}", s.message());
    return 1;
  }
  if (const std::string cuda = fq::daemon::cuda_line(config.engine, daemon.engine_names()); !cuda.empty())
    spdlog::info("{}", cuda);
  const std::string line = endpoints_json(daemon.endpoints());
  if (cl.print_endpoints) {
    std::printf("%s\n", line.c_str());
    std::fflush(stdout);
  }
  if (!cl.endpoints_file.empty()) std::ofstream(cl.endpoints_file) << line << "\n";
  fq::daemon::notify_service_manager("READY=1\nSTATUS=serving " + line);
  int sig = 0;
  while ((sig = fq::daemon::wait_for_stop_signal()) == SIGHUP) reload(source, cl, daemon);
  fq::daemon::notify_service_manager("STOPPING=1");
  spdlog::info("fqd: signal {} received, finishing frames in flight", sig);
  daemon.stop();
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return fq::tool_main("fqd", run, argc, argv); }
