// Which strings can name a stream, checked alike at every door that takes a stream id: the
// ingest topics and set_params (stream_admission.h), and the configuration's [streams.<id>]
// tables and [ingest] streams, which this wing reads before any stream exists.
#pragma once

#include <cstdint>
#include <string_view>

#include "common/status.h"

namespace fq::daemon {

/// Ok when `id` can name a stream: 1..max_bytes bytes of valid UTF-8 without C0/C1 control
/// characters, DEL, U+2028/U+2029 or bidirectional overrides and isolates (U+202A..U+202E,
/// U+2066..U+2069); otherwise a message that shows the id escaped. Every door that takes a
/// stream id (ingest topics, set_params, the config's [streams.*] and [ingest] streams, HTTP
/// paths) uses it.
Status validate_stream_id(std::string_view id, uint32_t max_bytes);

}  // namespace fq::daemon
