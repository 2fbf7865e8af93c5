// wire/symbol_decode.h against draco::DecodeSymbols: on streams draco::EncodeSymbols writes
// (random distributions, both schemes, every compression level), on damaged copies of them
// and on hand-made edge cases, both must take the same streams, give the same values and
// stop at the same byte. Inputs lie in buffers of exactly their size, so that a sanitizer
// build catches any read past them.
#include <draco/compression/entropy/symbol_encoding.h>
#include <draco/core/encoder_buffer.h>
#include <draco/core/options.h>
#include <gtest/gtest.h>

#include <cstring>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "tests/wire/symbol_decoders.h"

namespace fq::test_wire {
namespace {

using Bytes = std::vector<uint8_t>;

/// Both decoders on `bytes` from `at`; they must agree. Returns whether Draco took the stream.
bool expect_same(const Bytes& bytes, size_t at, uint32_t count, uint32_t components, SymbolRoom& room,
                 const std::string& what) {
  bool took = false;
  EXPECT_EQ("", compare_symbol_readings(bytes.data(), bytes.size(), at, count, components, room, &took))
      << what;
  return took;
}

/// How a distribution draws a value.
struct Distribution {
  const char* name;
  std::function<uint32_t(std::mt19937_64&)> draw;
};

std::vector<Distribution> distributions() {
  const auto geometric = [](double p) {
    return [p](std::mt19937_64& g) { return uint32_t(std::geometric_distribution<uint32_t>(p)(g)); };
  };
  const auto uniform = [](int bits) {
    return [bits](std::mt19937_64& g) { return uint32_t(g() & ((uint64_t(1) << bits) - 1)); };
  };
  // Values stay below 2^20: Draco's coder sizes its tables by the largest value (a decode of
  // 2^24-value symbols allocates 64 MB, and the test runs thousands).
  return {{"geometric 0.5", geometric(0.5)},
          {"geometric 0.02", geometric(0.02)},
          {"uniform 1 bit", uniform(1)},
          {"uniform 6 bits", uniform(6)},
          {"uniform 11 bits", uniform(11)},
          {"uniform 16 bits", uniform(16)},
          {"uniform 20 bits", uniform(20)},
          {"constant 0", [](std::mt19937_64&) { return 0u; }},
          {"constant 1000", [](std::mt19937_64&) { return 1000u; }},
          {"sparse", [](std::mt19937_64& g) { return g() % 500 == 0 ? uint32_t(g() % (1u << 20)) : 0u; }},
          {"mixed", [](std::mt19937_64& g) {
             return g() % 64 == 0 ? uint32_t(g() % (1u << 20))
                                  : uint32_t(std::geometric_distribution<uint32_t>(0.1)(g));
           }}};
}

/// draco::EncodeSymbols with a scheme (-1: Draco's choice) and a level, after `prefix` bytes;
/// nothing when Draco's encoder declines (more than 2^18 distinct values in the raw scheme).
std::optional<Bytes> encode(const std::vector<uint32_t>& values, uint32_t components, int scheme, int level,
                            const Bytes& prefix) {
  draco::Options options;
  if (scheme >= 0) draco::SetSymbolEncodingMethod(&options, static_cast<draco::SymbolCodingMethod>(scheme));
  draco::SetSymbolEncodingCompressionLevel(&options, level);
  draco::EncoderBuffer out;
  out.Encode(prefix.data(), prefix.size());
  if (!draco::EncodeSymbols(values.data(), int(values.size()), int(components), &options, &out))
    return std::nullopt;
  const auto* p = reinterpret_cast<const uint8_t*>(out.data());
  return Bytes(p, p + out.size());
}

TEST(SymbolDecode, DracosStreamsDecodeAsDracoDecodesThem) {
  std::mt19937_64 g(35);
  SymbolRoom room;
  int tagged = 0, raw = 0, declined = 0;
  const uint32_t lengths[] = {0, 1, 2, 3, 5, 64, 999, 4096, 40000};
  for (const Distribution& dist : distributions()) {
    for (const uint32_t length : lengths) {
      const uint32_t components = 1 + uint32_t(g() % 3);
      std::vector<uint32_t> values(size_t(length) * components);
      for (uint32_t& v : values) v = dist.draw(g);
      const Bytes prefix(g() % 8, uint8_t(g()));  // the stream need not start its buffer
      for (const int scheme : {-1, int(draco::SYMBOL_CODING_TAGGED), int(draco::SYMBOL_CODING_RAW)}) {
        // The level moves the raw scheme's precision; the tagged scheme has one.
        for (int level = 0; level <= (scheme == int(draco::SYMBOL_CODING_TAGGED) ? 0 : 10); ++level) {
          const auto bytes = encode(values, components, scheme, level, prefix);
          if (!bytes) {
            ++declined;
            continue;
          }
          if (bytes->size() > prefix.size()) ((*bytes)[prefix.size()] == 0 ? tagged : raw) += 1;
          const std::string what = std::string(dist.name) + ", " + std::to_string(values.size()) +
                                   " values of " + std::to_string(components) + ", scheme " +
                                   std::to_string(scheme) + ", level " + std::to_string(level);
          EXPECT_TRUE(expect_same(*bytes, prefix.size(), uint32_t(values.size()), components, room, what))
              << what;
        }
      }
    }
  }
  std::printf("  %d tagged and %d raw streams decoded alike; Draco's encoder declined %d\n", tagged, raw,
              declined);
  EXPECT_GT(tagged, 100);
  EXPECT_GT(raw, 100);
}

TEST(SymbolDecode, MillionValueStreamsDecodeAsDracoDecodesThem) {
  std::mt19937_64 g(1);
  SymbolRoom room;
  const std::vector<Distribution> all = distributions();
  for (const size_t d : {size_t(0), size_t(4), size_t(9)}) {
    std::vector<uint32_t> values(1'000'000);
    for (uint32_t& v : values) v = all[d].draw(g);
    for (const int scheme : {int(draco::SYMBOL_CODING_TAGGED), int(draco::SYMBOL_CODING_RAW)}) {
      for (const int level : {0, 7, 10}) {
        const auto bytes = encode(values, 1, scheme, level, {});
        ASSERT_TRUE(bytes);
        EXPECT_TRUE(expect_same(*bytes, 0, 1'000'000, 1, room, std::string(all[d].name) + " x 1e6"));
      }
    }
  }
}

/// Every way of damaging `bytes` the test tries: cut short, bits flipped, bytes replaced.
void damage_everywhere(const Bytes& bytes, size_t at, uint32_t count, uint32_t components, std::mt19937_64& g,
                       SymbolRoom& room, int& taken) {
  const size_t step = bytes.size() < 600 ? 1 : bytes.size() / 300;
  for (size_t n = 0; n < bytes.size(); n += step) {
    const Bytes cut(bytes.begin(), bytes.begin() + std::ptrdiff_t(n));
    taken += expect_same(cut, std::min(at, n), count, components, room, "cut to " + std::to_string(n));
  }
  for (int trial = 0; trial < 300; ++trial) {
    Bytes b = bytes;
    const size_t span = b.size() - at;
    // Mostly in the head (the tables, where a flip changes the most), sometimes anywhere.
    const size_t where = at + (trial % 2 == 0 ? g() % std::min<size_t>(span, 24) : g() % span);
    if (trial % 3 == 0) {
      b[where] = uint8_t(g());
    } else {
      b[where] ^= uint8_t(1u << (g() % 8));
    }
    taken += expect_same(b, at, count, components, room, "damaged at " + std::to_string(where));
  }
}

TEST(SymbolDecode, DamagedStreamsAreTakenOrRefusedAsDracoDoes) {
  std::mt19937_64 g(7);
  SymbolRoom room;
  int taken = 0;
  const std::vector<Distribution> all = distributions();
  for (const Distribution& dist : all) {
    for (const uint32_t length : {3u, 50u, 2000u}) {
      for (const int scheme : {int(draco::SYMBOL_CODING_TAGGED), int(draco::SYMBOL_CODING_RAW)}) {
        std::vector<uint32_t> values(size_t(length) * 3);
        for (uint32_t& v : values) v = dist.draw(g);
        const auto bytes = encode(values, 3, scheme, int(g() % 11), Bytes(4, 0x55));
        if (!bytes) continue;
        damage_everywhere(*bytes, 4, uint32_t(values.size()), 3, g, room, taken);
        // The same bytes read for another count of values, and with the other component count.
        expect_same(*bytes, 4, uint32_t(values.size()) + 3, 3, room, "more values than written");
        expect_same(*bytes, 4, uint32_t(values.size()), 1, room, "one component");
      }
    }
  }
  std::printf("  %d damaged streams taken by both\n", taken);
}

/// The stream head Draco's decoder reads: scheme, then (raw) the bit length, then a table.
Bytes head(std::initializer_list<uint8_t> b) { return Bytes(b); }

TEST(SymbolDecode, EdgeCasesDecodeAsDracoDecodesThem) {
  SymbolRoom room;
  std::vector<Bytes> cases = {
      head({}),                                    // nothing at all
      head({2}),                                   // an unknown scheme
      head({1, 0, 1, 0x00}),                       // raw bit length 0
      head({1, 19, 1, 0x00}),                      // raw bit length 19
      head({0, 0, 1, 0x00}),                       // tagged, no symbols
      head({1, 1, 0, 1, 0x00}),                    // raw, no symbols
      head({0, 1, 0x00, 1, 0x00}),                 // a table that sums to zero
      head({0, 2, 0xff, 0xff, 0x3f, 1, 0x00}),     // more than the precision
      head({0, 3, 0x0f, 1, 0x00}),                 // a zero run past the table
      head({0, 0x81, 0x80, 0x80, 0x80, 0x10}),     // a 5-byte count with bits past 32 (dropped)
      head({0, 0x80, 0x80, 0x80, 0x80, 0x80, 0}),  // a 6-byte count
  };
  // One symbol with the whole precision, then a state of 1 to 4 bytes: the 4-byte form (top
  // bits 11) reads bytes before a stream shorter than 4 bytes, as Draco does.
  for (uint8_t last : {0x00, 0x01, 0x40, 0x41, 0x80, 0x81, 0xc0, 0xc1}) {
    for (uint8_t size : {1, 2, 3, 4, 5}) {
      for (uint8_t bit_length : {0, 1, 33}) {  // tags: zero bits, one bit, more than 32
        // Tag table: symbol `bit_length` has probability 4096 (two extra bytes: 4096 << 2 | 2).
        Bytes b = {0, uint8_t(bit_length + 1)};
        if (bit_length > 0) b.push_back(uint8_t(((bit_length - 1) << 2) | 3));  // zeros before it
        b.insert(b.end(), {uint8_t(((4096 << 2) & 0xff) | 2), uint8_t((4096 << 2) >> 8), 0});
        b.push_back(size);
        for (uint8_t k = 0; k + 1 < size; ++k) b.push_back(uint8_t(k * 7));
        b.push_back(last);
        b.insert(b.end(), {0xa5, 0x5a});  // the value bits, then nothing: zeros past the end
        cases.push_back(b);
      }
    }
  }
  for (size_t i = 0; i < cases.size(); ++i) {
    for (const uint32_t count : {0u, 1u, 4u, 30u}) {
      const Bytes& b = cases[i];
      expect_same(b, 0, count, 1, room,
                  "case " + std::to_string(i) + ", " + std::to_string(count) + " values");
      expect_same(b, 0, count * 2, 2, room, "case " + std::to_string(i) + ", pairs");
    }
  }
}

}  // namespace
}  // namespace fq::test_wire
