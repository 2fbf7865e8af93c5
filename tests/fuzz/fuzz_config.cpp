// libFuzzer target: fqd's TOML configuration parser and validation.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "daemon/config/config.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  fq::daemon::DaemonConfig c;
  (void)fq::daemon::parse_config(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.toml", c);
  return 0;
}
