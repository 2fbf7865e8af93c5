// The service side of fqd's configuration: the HTTP listener ([http]) and the periodic
// stats log line ([stats]). Kept apart from the pipeline's keys in config.cpp.
#pragma once

#include <string>
#include <vector>

#include "common/status.h"

namespace fq::daemon {

class TomlReader;

struct HttpConfig {
  /// "host:port" to listen on ("" = no HTTP listener; port 0 = any free port).
  std::string listen;
  /// Folder of the live viewer (index.html and its node_modules). A relative path in a config
  /// file is taken from that file's folder; the built-in default from the working directory.
  std::string web_root = "web";
};

/// [ingest]: SUB-connect to producers' PUB endpoints as well as the PULL bind (scale-out).
struct SubIngestConfig {
  std::vector<std::string> connect;  ///< producers' PUB endpoints; empty = PULL only
  std::vector<std::string> streams;  ///< stream ids this fqd serves; empty = every stream
};

struct StatsLogConfig {
  double interval_s = 60.0;  ///< seconds between `[stats]` log lines; 0 = none
};

/// Reads [http], [stats] and [ingest] from the root table.
Status read_service_sections(TomlReader& root, HttpConfig& http, StatsLogConfig& stats,
                             SubIngestConfig& sub_ingest);

/// Reads [ingest] (connect, streams: arrays of strings).
Status read_sub_ingest(TomlReader& root, SubIngestConfig& out);

/// Splits "host:port" ("[::1]:8080" for IPv6); false when it is not of that form or the
/// port is outside 0..65535.
bool split_host_port(const std::string& listen, std::string& host, int& port);

}  // namespace fq::daemon
