// libFuzzer target: arbitrary bytes through draco::DecodeSymbols and its port
// (wire/symbol_decode.h); aborts where they differ (one takes the stream and the other does
// not, or they read other values, or stop at another byte). The first two bytes pick the
// components (1..3) and the values to read (up to 4095 groups); the stream is the rest, in a
// buffer of exactly its size, so that ASan sees any read past it.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "tests/wire/symbol_decoders.h"

// NOLINTNEXTLINE(readability-identifier-naming): libFuzzer names the entry point
extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 2) return 0;
  const uint32_t components = 1 + data[0] % 3;
  const uint32_t count = components * (((uint32_t(data[1]) << 4) | (data[0] >> 4)) % 4096);
  const std::vector<uint8_t> stream(data + 2, data + size);
  static fq::test_wire::SymbolRoom room;
  const std::string diff =
      fq::test_wire::compare_symbol_readings(stream.data(), stream.size(), 0, count, components, room);
  if (!diff.empty()) {
    std::fprintf(stderr, "fuzz_symbol_decode: %u values of %u: %s\n", count, components, diff.c_str());
    std::abort();
  }
  return 0;
}
