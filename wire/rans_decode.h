// Draco's rANS decoder (draco/compression/entropy/ans.h and rans_symbol_decoder.h), written
// again as host+device code: the probability table as Draco's RAnsSymbolDecoder::Create reads
// it, the state's start (read_init) and one symbol (rans_read), with Draco's precision rules.
// Each returns what Draco returns on every input, without Draco's allocations: Draco sizes a
// table by its symbol count (up to 64 a byte of input) and a lookup by the precision; here
// only the symbols with a probability are kept (each costs a byte of input, and they sum to
// the precision) and the lookup is kRansBuckets buckets, each the first symbol of its slots.
#pragma once

#include <cstdint>

#include "common/hd.h"
#include "wire/byte_reader.h"

namespace fq::wire::detail {

/// Lookup buckets of a table: a slot's symbol is its bucket's, or one of the next few.
inline constexpr int kRansBucketBits = 12;
inline constexpr uint32_t kRansBuckets = 1u << kRansBucketBits;
/// Draco's rANS precisions are 2^12 .. 2^20; a table has at most that many symbols.
inline constexpr int kRansMaxPrecisionBits = 20;

/// Draco's ComputeRAnsPrecisionFromUniqueSymbolsBitLength: 3/2 of the symbols' bit length,
/// clamped to 12..20 bits.
FQ_HD constexpr int rans_precision_bits(int symbol_bits) {
  const int p = (3 * symbol_bits) / 2;
  return p < 12 ? 12 : (p > kRansMaxPrecisionBits ? kRansMaxPrecisionBits : p);
}

/// What a decode step gives: done, refused (where Draco's decoder returns false), or out of
/// the caller's room (a workspace smaller than rans_symbol_room() promises: a bug, not input).
enum class SymbolStatus : uint8_t { kOk = 0, kRefused = 1, kNoRoom = 2 };

/// A symbol with a probability: its slots [cum, cum + prob) and its value (its index in the table).
struct RansSymbol {
  uint32_t cum;
  uint32_t prob;
  uint32_t val;
};

/// The caller's room for one table: `capacity` symbols and kRansBuckets buckets.
struct RansSpace {
  RansSymbol* symbols = nullptr;
  uint32_t capacity = 0;
  uint32_t* buckets = nullptr;
};

/// Enough symbols for any table read from `bytes` bytes at `precision_bits` (each symbol with a
/// probability takes at least one byte of the table, and there are at most 2^precision).
FQ_HD constexpr uint32_t rans_symbol_room(uint64_t bytes, int precision_bits) {
  const uint64_t most = uint64_t(1) << precision_bits;
  return static_cast<uint32_t>(bytes < most ? bytes : most);
}

/// A table read by read_rans_table. `num_symbols` is the count the table declares (zero
/// probabilities included); `count` of them are in `symbols`, in slot order.
struct RansTable {
  const RansSymbol* symbols = nullptr;
  uint32_t* buckets = nullptr;
  uint32_t num_symbols = 0;
  uint32_t count = 0;
  int precision_bits = 12;
  int bucket_shift = 0;  ///< slot >> bucket_shift is its bucket
  /// At 2^12 slots with values below 256 (every tagged table of Draco's encoder, and the
  /// narrowest raw ones) each bucket is one slot and holds its symbol packed (packed_slot), so
  /// a symbol costs one lookup.
  bool packed = false;
};

/// A slot of a packed table: prob - 1, cum and val in 12, 12 and 8 bits.
FQ_HD constexpr uint32_t packed_slot(const RansSymbol& y) {
  return (y.prob - 1) | (y.cum << 12) | (y.val << 24);
}

/// Draco's RAnsSymbolDecoder::Create (bitstream 2.0 and later) into `space`, except the lookup:
/// fill it with fill_rans_buckets (all of them, by one thread or by a team) before reading symbols.
/// A table that declares no symbols is read (kOk, count 0), as Draco reads it.
FQ_HD SymbolStatus read_rans_table(ByteReader& in, int precision_bits, RansSpace space, RansTable& t) {
  t = RansTable{};
  t.symbols = space.symbols;
  t.buckets = space.buckets;
  t.precision_bits = precision_bits;
  t.bucket_shift = precision_bits > kRansBucketBits ? precision_bits - kRansBucketBits : 0;
  uint32_t n = 0;
  if (!in.varint(n) || n / 64 > in.remaining()) return SymbolStatus::kRefused;
  t.num_symbols = n;
  const uint32_t precision = 1u << precision_bits;
  uint32_t cum = 0;
  for (uint32_t i = 0; i < n; ++i) {
    uint8_t b = 0;
    if (!in.get(b)) return SymbolStatus::kRefused;
    const int token = b & 3;  // 0..2: extra bytes of the probability; 3: a run of zeros
    if (token == 3) {
      const uint32_t run = b >> 2;
      if (i + run >= n) return SymbolStatus::kRefused;
      i += run;
      continue;
    }
    uint32_t prob = b >> 2;
    for (int e = 0; e < token; ++e) {
      uint8_t more = 0;
      if (!in.get(more)) return SymbolStatus::kRefused;
      prob |= uint32_t(more) << (8 * (e + 1) - 2);
    }
    if (prob == 0) continue;
    // Past the precision Draco refuses the table too, once read (or at the input's end first).
    cum += prob;
    if (cum > precision) return SymbolStatus::kRefused;
    if (t.count == space.capacity) return SymbolStatus::kNoRoom;
    space.symbols[t.count++] = RansSymbol{cum - prob, prob, i};
  }
  if (n != 0 && cum != precision) return SymbolStatus::kRefused;
  // Values rise with the slots: the last symbol has the largest.
  t.packed = precision_bits == kRansBucketBits && (t.count == 0 || t.symbols[t.count - 1].val < 256);
  return SymbolStatus::kOk;
}

/// Writes the buckets of symbols first, first + step, ...: each bucket b gets the symbol that
/// holds slot b << bucket_shift. One thread passes (0, 1); a team of n lanes passes (lane, n)
/// and together they write every bucket once.
FQ_HD void fill_rans_buckets(const RansTable& t, uint32_t first, uint32_t step) {
  const uint32_t s = uint32_t(t.bucket_shift), round = (1u << s) - 1;
  for (uint32_t k = first; k < t.count; k += step) {
    const RansSymbol& y = t.symbols[k];
    const uint32_t entry = t.packed ? packed_slot(y) : k;
    for (uint32_t b = (y.cum + round) >> s, end = (y.cum + y.prob + round) >> s; b < end; ++b)
      t.buckets[b] = entry;
  }
}

/// Draco's AnsDecoder over one rANS stream: its bytes and the state.
struct RansReader {
  const uint8_t* buf = nullptr;
  int offset = 0;  ///< bytes of buf not read yet (read backwards); below zero after a 4-byte start
  uint32_t state = 0;
  uint32_t low = 0;  ///< Draco's l_rans_base: 4 * precision
};

/// Draco's RAnsSymbolDecoder::StartDecoding and RAnsDecoder::read_init: the stream's byte count
/// (a varint), its bytes skipped in `in`, the state from its last bytes. Streams of up to
/// 2 GiB (Draco keeps the count in an int).
FQ_HD bool start_rans(ByteReader& in, int precision_bits, RansReader& r) {
  uint64_t bytes = 0;
  if (!in.varint(bytes) || bytes > in.remaining() || bytes > 0x7fffffffu) return false;
  const size_t at = in.pos;
  in.pos += size_t(bytes);
  const int n = static_cast<int>(bytes);
  if (n < 1) return false;
  const uint8_t* b = in.data + at;
  const uint32_t top = b[n - 1] >> 6;
  r.buf = b;
  // The top two bits say how many bytes hold the state; Draco takes a 4-byte state also from
  // a shorter stream, then with the bytes before it (which the stream's head always provides).
  const int width = int(top) + 1;
  if (n < width && (top < 3 || at + size_t(n) < 4)) return false;
  uint32_t s = 0;
  for (int k = 0; k < width; ++k) s |= uint32_t(b[n - width + k]) << (8 * k);
  r.offset = n - width;
  r.state = (s & ((1u << (8 * width - 2)) - 1)) + (4u << precision_bits);
  r.low = 4u << precision_bits;
  return r.state < r.low * 256;
}

/// Draco's RAnsDecoder::rans_read: one symbol of `t` (never reads outside the stream).
FQ_HD uint32_t read_rans_symbol(RansReader& r, const RansTable& t) {
  while (r.state < r.low && r.offset > 0) r.state = r.state * 256 + r.buf[--r.offset];
  const uint32_t quo = r.state >> t.precision_bits;
  const uint32_t rem = r.state & ((1u << t.precision_bits) - 1);
  if (t.packed) {
    const uint32_t e = t.buckets[rem];
    r.state = quo * ((e & 0xfffu) + 1) + rem - ((e >> 12) & 0xfffu);
    return e >> 24;
  }
  uint32_t k = t.buckets[rem >> t.bucket_shift];
  while (t.symbols[k].cum + t.symbols[k].prob <= rem) ++k;
  const RansSymbol y = t.symbols[k];
  r.state = quo * y.prob + rem - y.cum;
  return y.val;
}

}  // namespace fq::wire::detail
