// Where fqd's configuration comes from, in the usual service order: --config FILE, then
// $FQ_CONFIG, then /etc/fq/fqd.toml, then the built-in defaults (no file needed, any working
// directory). A file named by --config or $FQ_CONFIG must exist; /etc/fq/fqd.toml may not.
#pragma once

#include <string>

namespace fq::daemon {

struct ConfigSource {
  std::string path;  ///< the file to read; empty = built-in defaults
  std::string from;  ///< "--config", "$FQ_CONFIG", "/etc/fq/fqd.toml" or "built-in defaults"
};

inline constexpr const char* kSystemConfigPath = "/etc/fq/fqd.toml";

/// `flag` is --config's value ("" when not given); `env` is $FQ_CONFIG (null or "" when unset).
ConfigSource find_config(const std::string& flag, const char* env,
                         const std::string& system_path = kSystemConfigPath);

}  // namespace fq::daemon
