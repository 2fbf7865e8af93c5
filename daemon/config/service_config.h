// The service side of fqd's configuration: the HTTP listener ([http]) and the periodic
// stats log line ([stats]). Kept apart from the pipeline's keys in config.cpp.
#pragma once

#include <string>
#include <vector>

#include "common/status.h"
#include "daemon/config/http_config.h"

namespace fq::daemon {

class TomlReader;

/// [ingest]: SUB-connect to producers' PUB endpoints as well as the PULL bind (scale-out).
struct SubIngestConfig {
  std::vector<std::string> connect;  ///< producers' PUB endpoints; empty = PULL only
  std::vector<std::string> streams;  ///< stream ids this fqd serves; empty = every stream

  bool operator==(const SubIngestConfig&) const = default;
};

struct StatsLogConfig {
  double interval_s = 60.0;  ///< seconds between `[stats]` log lines; 0 = none

  bool operator==(const StatsLogConfig&) const = default;
};

/// Reads [http], [stats] and [ingest] from the root table.
Status read_service_sections(TomlReader& root, HttpConfig& http, StatsLogConfig& stats,
                             SubIngestConfig& sub_ingest);

/// Reads [ingest] (connect, streams: arrays of strings).
Status read_sub_ingest(TomlReader& root, SubIngestConfig& out);

}  // namespace fq::daemon
