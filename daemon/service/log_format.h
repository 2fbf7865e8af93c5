// fqd's log lines on stderr: plain text for people and journald, or one JSON object a line
// (--log-format json) for log collectors that index fields:
//   {"time":"2026-11-27T10:15:02.123Z","level":"info","logger":"fqd","msg":"fqd 0.1.0 ..."}
// The text stays the same words in both; only the framing differs.
#pragma once

#include <string>

namespace fq::daemon {

/// Makes spdlog's default logger "fqd" on stderr in `format` ("text" or "json").
void use_log_format(const std::string& format);

/// The spdlog pattern of the JSON form (time in UTC; %* is the message as a JSON string).
const char* json_log_pattern();

}  // namespace fq::daemon
