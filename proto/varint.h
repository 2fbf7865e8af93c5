// Unsigned LEB128 varints, as Draco writes them (EncodeVarint) and as the id runs use them.
#pragma once

#include <cstdint>

namespace fq::wire::detail {

/// Writes `v` at `at` (at most 5 bytes) and returns the end.
inline uint8_t* put_varint(uint32_t v, uint8_t* at) {
  while (v >= 0x80) {
    *at++ = static_cast<uint8_t>(v | 0x80);
    v >>= 7;
  }
  *at++ = static_cast<uint8_t>(v);
  return at;
}

}  // namespace fq::wire::detail
