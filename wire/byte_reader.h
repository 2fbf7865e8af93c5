// Reading Draco's bytes as draco::DecoderBuffer reads them, in host+device code: fixed-size
// little-endian values and Draco's varints, every read bounded by the buffer's end. The
// device decoder (kernels/cuda/chunk_decode.cu) and the symbol decoder (wire/symbol_decode.h)
// parse with it; it has no Draco dependency, so that nvcc compiles it for the GPU.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "common/hd.h"

namespace fq::wire::detail {

/// A position in [data, data + size): every read checks the end and fails there without
/// reading, as DecoderBuffer::Decode does (a failed read may still have moved `pos`, but the
/// callers give up on the first failure, as Draco's decoders do).
struct ByteReader {
  const uint8_t* data = nullptr;
  size_t size = 0;
  size_t pos = 0;

  FQ_HD size_t remaining() const { return size - pos; }

  /// A value of T as its bytes lie (Draco's DecoderBuffer::Decode<T>: little-endian hosts and GPUs).
  template <class T>
  FQ_HD bool get(T& v) {
    if (remaining() < sizeof(T)) return false;
    memcpy(&v, data + pos, sizeof(T));
    pos += sizeof(T);
    return true;
  }

  /// Reads a T and checks that it is `want`.
  template <class T>
  FQ_HD bool expect(T want) {
    T v{};
    return get(v) && v == want;
  }

  /// Draco's DecodeVarint for an unsigned T: at most sizeof(T) + 1 (+ 1 for 64 bits) bytes,
  /// the last without its top bit; bits past T's width are dropped, as Draco's shifts drop them.
  template <class T>
  FQ_HD bool varint(T& out) {
    constexpr int kMaxBytes = int(sizeof(T)) + 1 + int(sizeof(T) >> 3);
    T v = 0;
    for (int k = 0; k < kMaxBytes; ++k) {
      uint8_t b = 0;
      if (!get(b)) return false;
      if (7 * k < 8 * int(sizeof(T))) v |= static_cast<T>(T(b & 0x7f) << (7 * k));
      if ((b & 0x80) == 0) {
        out = v;
        return true;
      }
    }
    return false;
  }
};

}  // namespace fq::wire::detail
