// How fqd echoes a value that a peer or a file supplied (a stream id, a config value, a client
// address) in a log line or an error message: bounded and escaped, so that no value can make a
// line long, break it in two or act on a terminal.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace fq::daemon {

/// Bytes of a value that a log line or an error message echoes (a stream id, a config value):
/// enough to recognise it, and a 64 MiB value costs a line of ordinary length.
inline constexpr size_t kEchoBytes = 64;

/// `value` as a log line or a message may quote it: every byte outside printable ASCII, and
/// the backslash, as \xNN (so always valid UTF-8, one line, no terminal escapes), cut after
/// `max_chars` characters with "...(N bytes)" naming the value's whole size. Every echo of a
/// value that a peer or a file supplies goes through it.
std::string echo_value(std::string_view value, size_t max_chars = kEchoBytes);

}  // namespace fq::daemon
