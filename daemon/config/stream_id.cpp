#include "daemon/config/stream_id.h"

#include <cstdio>

#include "daemon/config/echo_value.h"

namespace fq::daemon {
namespace {

// Length of the UTF-8 sequence at s[i] (1..4) with its code point in `cp`, or 0 when it is not
// well formed (overlong forms, surrogates and code points above U+10FFFF are refused, as in
// RFC 3629).
size_t utf8_sequence(std::string_view s, size_t i, uint32_t& cp) {
  const auto b = [&](size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char c = b(i);
  cp = c;
  if (c < 0x80) return 1;
  size_t n;
  if ((c & 0xe0) == 0xc0)
    n = 2, cp = c & 0x1f;
  else if ((c & 0xf0) == 0xe0)
    n = 3, cp = c & 0x0f;
  else if ((c & 0xf8) == 0xf0)
    n = 4, cp = c & 0x07;
  else
    return 0;
  if (i + n > s.size()) return 0;
  for (size_t k = 1; k < n; ++k) {
    if ((b(i + k) & 0xc0) != 0x80) return 0;
    cp = (cp << 6) | (b(i + k) & 0x3f);
  }
  static constexpr uint32_t kMin[] = {0, 0, 0x80, 0x800, 0x10000};
  if (cp < kMin[n] || cp > 0x10ffff || (cp >= 0xd800 && cp <= 0xdfff)) return 0;
  return n;
}

// "202E" for U+202E.
std::string code_point_hex(uint32_t cp) {
  char hex[9];
  std::snprintf(hex, sizeof hex, "%04X", cp);
  return hex;
}

// Code points a stream id may not hold, because a terminal, a log viewer or a browser acts on
// them instead of showing them: C0 (ESC among them) and DEL, C1 (U+009B is a one-character CSI),
// the line and paragraph separators, and the bidirectional overrides and isolates (an id that
// reads as another one; CVE-2021-42574).
bool acts_on_display(uint32_t cp) {
  return cp < 0x20 || (cp >= 0x7f && cp <= 0x9f) || cp == 0x2028 || cp == 0x2029 ||
         (cp >= 0x202a && cp <= 0x202e) || (cp >= 0x2066 && cp <= 0x2069);
}

}  // namespace

Status validate_stream_id(std::string_view id, uint32_t max_bytes) {
  if (id.empty()) return invalid_input("empty stream id");
  if (id.size() > max_bytes)
    return invalid_input("stream id of " + std::to_string(id.size()) + " bytes is over the cap of " +
                         std::to_string(max_bytes) + " (caps.max_stream_id_bytes): '" + echo_value(id) + "'");
  for (size_t i = 0; i < id.size();) {
    uint32_t cp = 0;
    const size_t n = utf8_sequence(id, i, cp);
    if (n == 0) return invalid_input("stream id is not valid UTF-8: '" + echo_value(id) + "'");
    if (acts_on_display(cp))
      return invalid_input(
          "stream id holds a control character, a line separator or a bidirectional formatting "
          "character (U+" +
          code_point_hex(cp) + "): '" + echo_value(id) + "'");
    i += n;
  }
  return {};
}

}  // namespace fq::daemon
