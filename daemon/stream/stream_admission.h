// Which topics become streams. A stream costs state (settings, counters, latency windows,
// a slot), so only ids that pass these checks get any; everything else is refused and
// counted per reason in a fixed set of counters, never per topic.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "common/status.h"
#include "daemon/config/stream_id.h"
#include "daemon/stream/reason_counters.h"

namespace fq::daemon {

struct Caps;

enum class Refusal {
  kBadStreamId,
  kMalformed,
  kNotAllowed,
  kTooManyStreams,
  kUnauthenticated,
  kOversized,      ///< an ingest or control message over its bound on parts or bytes
  kSubscriptions,  ///< a subscriber over caps.max_subscriptions / max_subscription_bytes (cut)
  kUndecodable,    ///< a frame from a producer without CURVE that failed to decode (dropped)
  kCount
};

/// Name of a refusal reason as it appears in counters and logs.
const char* refusal_name(Refusal r);

/// True when the allow-list is empty or names `id` exactly or by a "prefix*" entry.
bool stream_allowed(std::string_view id, const std::vector<std::string>& allowed);

/// The one check of a stream id on every door (ingest, SUB ingest, control, HTTP): valid
/// (validate_stream_id with caps.max_stream_id_bytes) and allowed (caps.allowed_streams). On
/// failure `why` (when given) says which, and the message shows the id escaped.
Status check_stream_id(std::string_view id, const Caps& caps, Refusal* why = nullptr);

/// echo_value(id, max_chars) (daemon/config/echo_value.h): safe for logs and for protobuf string fields.
std::string printable_id(std::string_view id, size_t max_chars = 64);

/// Refusals by reason; thread-safe.
using RefusalCounters = ReasonCounters<Refusal>;

}  // namespace fq::daemon
