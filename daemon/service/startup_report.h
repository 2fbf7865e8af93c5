// What fqd says first: its version and where its configuration came from, then one line for
// each thing that is off (HTTP, CURVE, the stats line, CUDA), so that an operator reading the
// start of a log knows what this process does not do without reading its configuration.
#pragma once

#include <string>
#include <vector>

#include "daemon/config/config.h"
#include "daemon/service/config_lookup.h"

namespace fq::daemon {

/// "fqd 0.1.0 (CUDA engine: compiled in) starting, pid 4242, configuration from --config (a.toml)".
std::string start_line(const ConfigSource& source, long pid);

/// One line for each feature this configuration leaves off, known before the engines exist.
std::vector<std::string> off_lines(const DaemonConfig& config);

/// After the engines are made: a line when no CUDA engine runs, saying why (not compiled in,
/// engine.kind = cpu, or no GPU found); empty when one does.
std::string cuda_line(const EngineConfig& engine, const std::vector<std::string>& engine_names);

}  // namespace fq::daemon
