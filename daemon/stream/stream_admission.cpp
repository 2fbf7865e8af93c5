#include "daemon/stream/stream_admission.h"

#include "daemon/config/config.h"
#include "daemon/config/echo_value.h"

namespace fq::daemon {

const char* refusal_name(Refusal r) {
  switch (r) {
    case Refusal::kBadStreamId:
      return "bad_stream_id";
    case Refusal::kMalformed:
      return "malformed";
    case Refusal::kNotAllowed:
      return "not_allowed";
    case Refusal::kTooManyStreams:
      return "too_many_streams";
    case Refusal::kUnauthenticated:
      return "unauthenticated";
    case Refusal::kOversized:
      return "oversized";
    case Refusal::kSubscriptions:
      return "subscriptions";
    case Refusal::kUndecodable:
      return "undecodable";
    case Refusal::kCount:
      break;
  }
  return "?";
}

std::string printable_id(std::string_view id, size_t max_chars) { return echo_value(id, max_chars); }

Status check_stream_id(std::string_view id, const Caps& caps, Refusal* why) {
  if (Status s = validate_stream_id(id, caps.max_stream_id_bytes); !s.ok()) {
    if (why) *why = Refusal::kBadStreamId;
    return s;
  }
  if (!stream_allowed(id, caps.allowed_streams)) {
    if (why) *why = Refusal::kNotAllowed;
    return invalid_input("stream '" + printable_id(id) + "' is not in caps.allowed_streams");
  }
  return {};
}

bool stream_allowed(std::string_view id, const std::vector<std::string>& allowed) {
  if (allowed.empty()) return true;
  for (const std::string& a : allowed) {
    if (!a.empty() && a.back() == '*') {
      if (id.substr(0, a.size() - 1) == std::string_view(a).substr(0, a.size() - 1)) return true;
    } else if (id == a) {
      return true;
    }
  }
  return false;
}

}  // namespace fq::daemon
