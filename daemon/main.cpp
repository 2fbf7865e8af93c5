// fqd: the streaming daemon. Usage: fqd [--config configs/fqd.toml]
// Configuration: --config, else $FQ_CONFIG, else /etc/fq/fqd.toml, else built-in defaults.
// SIGINT/SIGTERM stop it (frames in flight are finished); SIGHUP reloads the file (what a
// reload may change: daemon/config_reload.h).
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>

#include "common/version.h"
#include "daemon/config.h"
#include "daemon/config_lookup.h"
#include "daemon/daemon.h"
#include "daemon/signals.h"

namespace {

std::string endpoints_json(const fq::daemon::BoundEndpoints& e) {
  nlohmann::json j{{"ingest", e.ingest}, {"publish", e.publish}, {"control", e.control}};
  if (!e.http.empty()) j["http"] = e.http;
  return j.dump();
}

// `config` is left as it is (default-constructed by the caller) for the built-in defaults.
fq::Status load(const fq::daemon::ConfigSource& source, fq::daemon::DaemonConfig& config) {
  return source.path.empty() ? fq::Status{} : fq::daemon::load_config(source.path, config);
}

// SIGHUP: the file again, applied whole or not at all (an invalid or empty file, or one that
// changes a setting only a restart can change, changes nothing). `log_level`: --log-level.
void reload(const fq::daemon::ConfigSource& source, const std::string& log_level, fq::daemon::Daemon& daemon) {
  if (source.path.empty()) {
    spdlog::info("fqd: SIGHUP ignored: running on built-in defaults, no configuration file to reload");
    return;
  }
  fq::daemon::DaemonConfig fresh;
  fq::Status s = fq::daemon::load_config(source.path, fresh, /*allow_empty=*/false);
  if (!log_level.empty()) fresh.log_level = log_level;
  if (s.ok()) s = daemon.reload(fresh);
  if (!s.ok()) {
    spdlog::error("fqd: SIGHUP: {} not reloaded, settings unchanged: {}", source.path, s.message());
    return;
  }
  spdlog::info("fqd: SIGHUP: reloaded {} (streams, caps, client keys, HTTP access, log level)", source.path);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"fqd: filters and clusters streamed mesh frames within a latency budget"};
  app.set_version_flag("--version", fq::version_line("fqd"));
  std::string config_path, log_level, endpoints_file;
  bool print_endpoints = false, check_only = false;
  app.add_option("-c,--config", config_path,
                 "TOML configuration file (default: $FQ_CONFIG, else /etc/fq/fqd.toml, else built-in defaults)");
  app.add_option("--log-level", log_level,
                 "override log_level: trace, debug, info, warn, error, critical, off");
  app.add_flag("--print-endpoints", print_endpoints,
               "print the bound endpoints as one JSON line on stdout once listening (for ports given as *)");
  app.add_option("--endpoints-file", endpoints_file, "also write that JSON line to this file once listening");
  app.add_flag("--check-config", check_only, "validate the configuration and exit");
  CLI11_PARSE(app, argc, argv);
  // Logs go to stderr: stdout carries only the --print-endpoints line.
  spdlog::set_default_logger(spdlog::stderr_color_mt("fqd"));

  const fq::daemon::ConfigSource source = fq::daemon::find_config(config_path, std::getenv("FQ_CONFIG"));
  fq::daemon::DaemonConfig config;
  if (fq::Status s = load(source, config); !s.ok()) {
    std::fprintf(stderr, "fqd: invalid configuration: %s\n", s.message().c_str());
    return 2;
  }
  if (!log_level.empty()) {
    if (!fq::daemon::valid_log_level(log_level)) {
      std::fprintf(stderr,
                   "fqd: --log-level must be one of trace, debug, info, warn, error, critical, off\n");
      return 2;
    }
    config.log_level = log_level;
  }
  if (check_only) {
    std::printf("%s: configuration is valid\n", source.path.empty() ? source.from.c_str() : source.path.c_str());
    return 0;
  }
  spdlog::set_level(spdlog::level::from_str(config.log_level));
  spdlog::info("fqd: configuration from {}{}", source.from, source.path.empty() || source.path == source.from ? "" : " (" + source.path + ")");

  fq::daemon::block_stop_signals();  // before any thread exists, so all of them inherit it
  fq::daemon::Daemon daemon(config);
  if (fq::Status s = daemon.start(); !s.ok()) {
    spdlog::critical("fqd: cannot start: {}", s.message());
    return 1;
  }
  const std::string line = endpoints_json(daemon.endpoints());
  if (print_endpoints) {
    std::printf("%s\n", line.c_str());
    std::fflush(stdout);
  }
  if (!endpoints_file.empty()) std::ofstream(endpoints_file) << line << "\n";
  int sig = 0;
  while ((sig = fq::daemon::wait_for_stop_signal()) == SIGHUP) reload(source, log_level, daemon);
  spdlog::info("fqd: signal {} received, finishing frames in flight", sig);
  daemon.stop();
  return 0;
}
