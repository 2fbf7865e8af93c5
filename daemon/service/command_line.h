// fqd's command line: where the configuration comes from, and flags for the overrides an
// operator needs most (engine, HTTP listener, log level and format, shard), applied over the
// file. A usage error exits 2, like an invalid configuration, so that a service manager that
// does not restart on 2 (packaging/fqd.service) does not restart a typo in a loop.
#pragma once

#include <optional>
#include <string>

#include "common/status.h"
#include "daemon/config/config.h"

namespace fq::daemon {

struct CommandLine {
  std::string config_path;                 ///< --config; "" = $FQ_CONFIG, /etc/fq/fqd.toml, built-in defaults
  std::optional<std::string> log_level;    ///< --log-level
  std::optional<std::string> engine;       ///< --engine auto|cuda|cpu
  std::optional<std::string> http_listen;  ///< --http-listen HOST:PORT ("" = no HTTP)
  std::optional<std::string> shard;        ///< --shard K/N
  std::string log_format = "text";         ///< --log-format text|json
  std::string endpoints_file;
  int shard_map = 0;  ///< --shard-map N: print each [ingest] stream's shard of N and exit
  bool print_endpoints = false;
  bool check_only = false;
};

/// Parses argv into `out`. nullopt: go on; otherwise the exit status, after printing what
/// CLI11 prints: 0 for --help and --version, 2 for every usage error.
std::optional<int> parse_command_line(int argc, char** argv, CommandLine& out);

/// Applies the flags over the loaded configuration; kInvalidArgument naming the flag.
/// `shard_streams` receives the [ingest] streams kept by --shard.
Status apply_command_line(const CommandLine& cl, DaemonConfig& config,
                          std::vector<std::string>* shard_streams = nullptr);

}  // namespace fq::daemon
