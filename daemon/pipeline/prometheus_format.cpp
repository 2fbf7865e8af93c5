#include "daemon/pipeline/prometheus_format.h"

#include <cstdio>

namespace fq::daemon {

void append_family(std::string& out, const char* name, const char* type, const char* help) {
  out += std::string("# HELP ") + name + " " + help + "\n# TYPE " + name + " " + type + "\n";
}

void append_reason_counts(std::string& out, const char* name, const char* help,
                          const std::vector<std::pair<std::string, uint64_t>>& counts) {
  append_family(out, name, "counter", help);
  for (const auto& [reason, n] : counts)
    out += std::string(name) + "{reason=\"" + escape_label_value(reason) + "\"} " + std::to_string(n) + "\n";
}

// %.17g round-trips any double.
std::string metric_number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string escape_label_value(const std::string& value) {
  std::string out;
  for (char c : value) {
    if (c == '\\')
      out += "\\\\";
    else if (c == '"')
      out += "\\\"";
    else if (c == '\n')
      out += "\\n";
    else
      out += c;
  }
  return out;
}

}  // namespace fq::daemon
