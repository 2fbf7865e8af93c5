// The audit trail of a stream's settings: every change, from the control socket or a SIGHUP
// reload, is logged as what changed, from what, to what:
//   cam0 sigma_s 1.5 -> 3 (control)
// Keys are the control protocol's (ParamOverrides field names, as `fqctl set` takes them)
// and the config file's for what only the file sets (budget_ms, position_bits, ...).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "daemon/config/stream_settings.h"
#include "daemon/pipeline/log_limiter.h"

namespace fq::daemon {

/// Every setting of `s` as (key, value) in a fixed order; enums by their lower-case names.
std::vector<std::pair<std::string, std::string>> settings_fields(const StreamSettings& s);

/// "key old -> new" for each setting that differs, in settings_fields' order.
std::vector<std::string> settings_changes(const StreamSettings& before, const StreamSettings& after);

/// Logs one info line per change: "<stream> <key> <old> -> <new> (<cause>)". With a `limiter`
/// (changes any peer can cause: the control socket) one request's lines pass or are held back
/// together, so that an audited change is never logged in part.
void log_settings_changes(const std::string& stream_id, const StreamSettings& before,
                          const StreamSettings& after, const char* cause, LogLimiter* limiter = nullptr);

}  // namespace fq::daemon
