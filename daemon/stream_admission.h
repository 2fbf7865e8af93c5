// Which topics become streams. A stream costs state (settings, counters, latency windows,
// a slot), so only ids that pass these checks get any; everything else is refused and
// counted per reason in a fixed set of counters, never per topic.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "common/status.h"
#include "daemon/reason_counters.h"

namespace fq::daemon {

struct Caps;

enum class Refusal { kBadStreamId, kMalformed, kNotAllowed, kTooManyStreams, kUnauthenticated, kCount };

/// Name of a refusal reason as it appears in counters and logs.
const char* refusal_name(Refusal r);

/// Ok when `id` can name a stream: 1..max_bytes bytes of valid UTF-8 without control
/// characters; otherwise a message that shows the id escaped.
Status validate_stream_id(std::string_view id, uint32_t max_bytes);

/// True when the allow-list is empty or names `id` exactly or by a "prefix*" entry.
bool stream_allowed(std::string_view id, const std::vector<std::string>& allowed);

/// `id` with every byte outside printable ASCII as \xNN, cut to `max_chars`: safe for
/// logs and for protobuf string fields (always valid UTF-8).
std::string printable_id(std::string_view id, size_t max_chars = 64);

/// Refusals by reason; thread-safe.
using RefusalCounters = ReasonCounters<Refusal>;

/// At most `per_second` messages a second pass; the rest are counted, and the next message
/// that passes reports how many were held back. Keeps junk traffic from flooding the log.
class LogLimiter {
 public:
  explicit LogLimiter(int per_second = 5) : per_second_(per_second) {}
  /// True when a message may be logged now; `suppressed` is then the number held back since.
  bool allow(int64_t now_ns, uint64_t& suppressed);

 private:
  int per_second_;
  int64_t window_start_ns_ = 0;
  int in_window_ = 0;
  uint64_t suppressed_ = 0;
};

}  // namespace fq::daemon
