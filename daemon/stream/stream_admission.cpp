#include "daemon/stream/stream_admission.h"

#include <cstdio>

#include "daemon/config/config.h"

namespace fq::daemon {
namespace {

// Length of the UTF-8 sequence at s[i] (1..4), or 0 when it is not well formed
// (overlong forms, surrogates and code points above U+10FFFF are refused, as in RFC 3629).
size_t utf8_sequence(std::string_view s, size_t i) {
  const auto b = [&](size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char c = b(i);
  if (c < 0x80) return 1;
  size_t n;
  uint32_t cp;
  if ((c & 0xe0) == 0xc0) n = 2, cp = c & 0x1f;
  else if ((c & 0xf0) == 0xe0) n = 3, cp = c & 0x0f;
  else if ((c & 0xf8) == 0xf0) n = 4, cp = c & 0x07;
  else return 0;
  if (i + n > s.size()) return 0;
  for (size_t k = 1; k < n; ++k) {
    if ((b(i + k) & 0xc0) != 0x80) return 0;
    cp = (cp << 6) | (b(i + k) & 0x3f);
  }
  static constexpr uint32_t kMin[] = {0, 0, 0x80, 0x800, 0x10000};
  if (cp < kMin[n] || cp > 0x10ffff || (cp >= 0xd800 && cp <= 0xdfff)) return 0;
  return n;
}

}  // namespace

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
    case Refusal::kCount:
      break;
  }
  return "?";
}

std::string printable_id(std::string_view id, size_t max_chars) {
  std::string out;
  for (unsigned char c : id) {
    if (out.size() >= max_chars) {
      out += "...";
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

Status validate_stream_id(std::string_view id, uint32_t max_bytes) {
  if (id.empty()) return invalid_input("empty stream id");
  if (id.size() > max_bytes)
    return invalid_input("stream id of " + std::to_string(id.size()) + " bytes is over the cap of " +
                         std::to_string(max_bytes) + " (caps.max_stream_id_bytes): '" + printable_id(id) + "'");
  for (size_t i = 0; i < id.size();) {
    const size_t n = utf8_sequence(id, i);
    if (n == 0) return invalid_input("stream id is not valid UTF-8: '" + printable_id(id) + "'");
    if (n == 1 && (static_cast<unsigned char>(id[i]) < 0x20 || id[i] == 0x7f))
      return invalid_input("stream id holds a control character: '" + printable_id(id) + "'");
    i += n;
  }
  return {};
}

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
