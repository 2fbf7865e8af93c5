// Unsigned LEB128 varints, as Draco writes them (EncodeVarint) and as the id runs use them;
// get_varint also reads connectivity indices on the device (kernels/cuda/chunk_decode.cu).
#pragma once

#include <cstddef>
#include <cstdint>

#include "common/hd.h"

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

/// Reads one varint of at most `max_bytes` bytes (5: any 32-bit value) at data[pos] into `v`;
/// false at the end of `size` bytes, on a longer one, or on bits past 32.
FQ_HD bool get_varint(const uint8_t* data, size_t size, size_t& pos, uint32_t& v, int max_bytes = 5) {
  v = 0;
  for (int shift = 0; shift < 7 * max_bytes && shift < 35; shift += 7) {
    if (pos >= size) return false;
    const uint8_t b = data[pos++];
    if (shift == 28 && (b & 0xf0) != 0) return false;
    v |= uint32_t(b & 0x7f) << shift;
    if ((b & 0x80) == 0) return true;
  }
  return false;
}

}  // namespace fq::wire::detail
