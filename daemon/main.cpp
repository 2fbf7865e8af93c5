// fqd: the streaming daemon. Usage: fqd --config configs/fqd.toml
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>

#include "common/version.h"
#include "daemon/config.h"
#include "daemon/daemon.h"
#include "daemon/signals.h"

namespace {

std::string endpoints_json(const fq::daemon::BoundEndpoints& e) {
  return nlohmann::json{{"ingest", e.ingest}, {"publish", e.publish}, {"control", e.control}}.dump();
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"fqd: filters and clusters streamed mesh frames within a latency budget"};
  app.set_version_flag("--version", fq::version_line("fqd"));
  std::string config_path = "configs/fqd.toml", log_level, endpoints_file;
  bool print_endpoints = false, check_only = false;
  app.add_option("-c,--config", config_path, "TOML configuration file")->capture_default_str();
  app.add_option("--log-level", log_level,
                 "override log_level: trace, debug, info, warn, error, critical, off");
  app.add_flag("--print-endpoints", print_endpoints,
               "print the bound endpoints as one JSON line on stdout once listening (for ports given as *)");
  app.add_option("--endpoints-file", endpoints_file, "also write that JSON line to this file once listening");
  app.add_flag("--check-config", check_only, "validate the configuration and exit");
  CLI11_PARSE(app, argc, argv);
  // Logs go to stderr: stdout carries only the --print-endpoints line.
  spdlog::set_default_logger(spdlog::stderr_color_mt("fqd"));

  fq::daemon::DaemonConfig config;
  if (fq::Status s = fq::daemon::load_config(config_path, config); !s.ok()) {
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
    std::printf("%s: configuration is valid\n", config_path.c_str());
    return 0;
  }
  spdlog::set_level(spdlog::level::from_str(config.log_level));

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
  const int sig = fq::daemon::wait_for_stop_signal();
  spdlog::info("fqd: signal {} received, finishing frames in flight", sig);
  daemon.stop();
  return 0;
}
