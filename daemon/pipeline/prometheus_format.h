// The pieces of Prometheus' text exposition format (version 0.0.4) that every family fqd
// writes is made of. Apart from prometheus_text.h (the streams' families) so that the threads
// and the process can write their own families without depending on the stream registry.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace fq::daemon {

/// "# HELP name help" and "# TYPE name type" lines, for families written elsewhere.
void append_family(std::string& out, const char* name, const char* type, const char* help);

/// A counter family by reason: `name`{reason="…"} for each (reason, count), zeros included.
void append_reason_counts(std::string& out, const char* name, const char* help,
                          const std::vector<std::pair<std::string, uint64_t>>& counts);

/// A sample value that round-trips (%.17g).
std::string metric_number(double v);

/// A label value with \, " and newline escaped as the format requires.
std::string escape_label_value(const std::string& value);

}  // namespace fq::daemon
