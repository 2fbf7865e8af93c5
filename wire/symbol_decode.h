// draco::DecodeSymbols (draco/compression/entropy/symbol_decoding.cc), written again as
// host+device code: Draco's two schemes, chosen per stream by its encoder. Tagged: a rANS
// stream of bit lengths (5-bit symbols, precision 2^12), one per group of `components` values,
// then the values' low bits, least significant first, from the rest of the buffer. Raw: each
// value a rANS symbol, at the precision its stored bit length (1..18) gives. Decodes what
// Draco decodes and refuses what Draco refuses, on every input (tests/wire/symbol_decode_test.cpp
// and the fuzz target fuzz_symbol_decode compare both), with no reads outside [data, data + size).
#pragma once

#include <cstdint>

#include "common/hd.h"
#include "wire/byte_reader.h"
#include "wire/rans_decode.h"

namespace fq::wire::detail {

/// Draco's SymbolCodingMethod values.
inline constexpr uint8_t kSymbolCodingTagged = 0;
inline constexpr uint8_t kSymbolCodingRaw = 1;
/// Draco's tagged scheme: bit lengths of at most 32 bits as 5-bit symbols.
inline constexpr int kTagPrecisionBits = rans_precision_bits(5);

/// Bits [offset, offset + n) of a bit stream of `bits` bits, least significant first, as Draco's
/// DecoderBuffer bit decoder reads them: zeros past the end. Its reads past the end also leave
/// it at the end, so the read that follows n bits of reads starts at min(n, bits), which lets
/// a team read a stream's values at once.
FQ_HD uint32_t bits_at(const uint8_t* data, uint64_t bits, uint64_t offset, uint32_t n) {
  const uint64_t end = offset + n < bits ? offset + n : bits;
  if (end <= offset) return 0;
  const uint64_t first = offset >> 3, last = (end - 1) >> 3;
  uint64_t word = 0;
  for (uint64_t i = first; i <= last; ++i) word |= uint64_t(data[i]) << (8 * (i - first));
  return static_cast<uint32_t>((word >> (offset & 7)) & ((uint64_t(1) << (end - offset)) - 1));
}

/// The tagged scheme's table and streams, read up to its first symbol (Draco's
/// DecodeTaggedSymbols before its loop). The bits start where `in` stands after this.
FQ_HD SymbolStatus start_tagged(ByteReader& in, RansSpace space, RansTable& tags, RansReader& r) {
  const SymbolStatus s = read_rans_table(in, kTagPrecisionBits, space, tags);
  if (s != SymbolStatus::kOk) return s;
  if (!start_rans(in, kTagPrecisionBits, r) || tags.num_symbols == 0) return SymbolStatus::kRefused;
  return SymbolStatus::kOk;
}

/// The raw scheme's table and stream, read up to its first symbol (Draco's DecodeRawSymbols
/// and DecodeRawSymbolsInternal before their loop).
FQ_HD SymbolStatus start_raw(ByteReader& in, RansSpace space, RansTable& t, RansReader& r) {
  uint8_t bit_length = 0;
  if (!in.get(bit_length) || bit_length < 1 || bit_length > 18) return SymbolStatus::kRefused;
  const int precision_bits = rans_precision_bits(bit_length);
  const SymbolStatus s = read_rans_table(in, precision_bits, space, t);
  if (s != SymbolStatus::kOk) return s;
  if (t.num_symbols == 0 || !start_rans(in, precision_bits, r)) return SymbolStatus::kRefused;
  return SymbolStatus::kOk;
}

/// The tagged scheme's bit lengths, each into the first slot of its group (out[0],
/// out[components], ...), as Draco's DecodeTaggedSymbols reads them (it refuses one over 32).
FQ_HD SymbolStatus read_tags(const RansTable& tags, RansReader& r, uint32_t num_values, uint32_t components,
                             uint32_t* out) {
  for (uint32_t i = 0; i < num_values; i += components) {
    const uint32_t length = read_rans_symbol(r, tags);
    out[i] = length;
    if (length > 32) return SymbolStatus::kRefused;
  }
  return SymbolStatus::kOk;
}

/// The tagged scheme's values after read_tags: each group's `length` low bits, least
/// significant first, from where `in` stands; `in` moved past them (Draco's EndBitDecoding).
FQ_HD void read_tagged_bits(ByteReader& in, uint32_t num_values, uint32_t components, uint32_t* out) {
  const uint8_t* data = in.data + in.pos;
  const uint64_t bits = 8 * uint64_t(in.remaining());
  uint64_t offset = 0;
  for (uint32_t i = 0; i < num_values; i += components) {
    const uint32_t length = out[i];
    for (uint32_t j = 0; j < components; ++j, offset = offset + length < bits ? offset + length : bits)
      out[i + j] = bits_at(data, bits, offset, length);
  }
  in.pos += size_t((offset + 7) / 8);
}

/// A symbol stream read up to its first symbol: its scheme, table and rANS stream.
struct SymbolStream {
  uint8_t scheme = kSymbolCodingTagged;
  RansTable table;
  RansReader reader;
};

/// draco::DecodeSymbols(num_values, components, ...) up to its first symbol, with `space` for
/// the table (rans_symbol_room(in.remaining(), kRansMaxPrecisionBits) symbols always suffice).
/// num_values must be a multiple of components (Draco writes past num_values otherwise).
/// Then fill_rans_buckets(s.table, ...) and read_symbols, unless num_values is 0: Draco reads
/// nothing then, not even the scheme.
FQ_HD SymbolStatus start_symbols(ByteReader& in, uint32_t num_values, uint32_t components, RansSpace space,
                                 SymbolStream& s) {
  if (num_values == 0) return SymbolStatus::kOk;
  if (components == 0 || num_values % components != 0) return SymbolStatus::kRefused;
  if (!in.get(s.scheme)) return SymbolStatus::kRefused;
  if (s.scheme == kSymbolCodingTagged) return start_tagged(in, space, s.table, s.reader);
  if (s.scheme == kSymbolCodingRaw) return start_raw(in, space, s.table, s.reader);
  return SymbolStatus::kRefused;
}

/// The values of a started stream (buckets filled) into out[0, num_values).
FQ_HD SymbolStatus read_symbols(ByteReader& in, SymbolStream& s, uint32_t num_values, uint32_t components,
                                uint32_t* out) {
  if (num_values == 0) return SymbolStatus::kOk;
  if (s.scheme == kSymbolCodingTagged) {
    const SymbolStatus tags = read_tags(s.table, s.reader, num_values, components, out);
    if (tags == SymbolStatus::kOk) read_tagged_bits(in, num_values, components, out);
    return tags;
  }
  for (uint32_t i = 0; i < num_values; ++i) out[i] = read_rans_symbol(s.reader, s.table);
  return SymbolStatus::kOk;
}

/// draco::DecodeSymbols(num_values, components, in, out) by one thread (see start_symbols).
FQ_HD SymbolStatus decode_symbols(ByteReader& in, uint32_t num_values, uint32_t components, RansSpace space,
                                  uint32_t* out) {
  SymbolStream s;
  const SymbolStatus started = start_symbols(in, num_values, components, space, s);
  if (started != SymbolStatus::kOk || num_values == 0) return started;
  fill_rans_buckets(s.table, 0, 1);
  return read_symbols(in, s, num_values, components, out);
}

}  // namespace fq::wire::detail
