#include "daemon/service/config_lookup.h"

#include <filesystem>

namespace fq::daemon {

ConfigSource find_config(const std::string& flag, const char* env, const std::string& system_path) {
  if (!flag.empty()) return {flag, "--config"};
  if (env && *env) return {env, "$FQ_CONFIG"};
  std::error_code ec;
  if (std::filesystem::is_regular_file(system_path, ec)) return {system_path, system_path};
  return {"", "built-in defaults"};
}

}  // namespace fq::daemon
