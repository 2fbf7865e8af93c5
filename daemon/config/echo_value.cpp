#include "daemon/config/echo_value.h"

#include <cstdio>

namespace fq::daemon {

std::string echo_value(std::string_view value, size_t max_chars) {
  std::string out;
  for (unsigned char c : value) {
    if (out.size() >= max_chars) {
      out += "...(" + std::to_string(value.size()) + " bytes)";
      break;
    }
    if (c >= 0x20 && c < 0x7f && c != '\\') {
      out.push_back(static_cast<char>(c));
    } else {
      char hex[5];
      std::snprintf(hex, sizeof hex, "\\x%02x", c);
      out += hex;
    }
  }
  return out;
}

}  // namespace fq::daemon
