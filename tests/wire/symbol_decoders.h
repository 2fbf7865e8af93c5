// draco::DecodeSymbols and its port (wire/symbol_decode.h) on the same bytes, for the tests
// and the fuzz target that compare them.
#pragma once

#include <draco/compression/config/compression_shared.h>
#include <draco/compression/entropy/symbol_decoding.h>
#include <draco/core/decoder_buffer.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "wire/symbol_decode.h"

namespace fq::test_wire {

/// What a decoder made of a symbol stream: whether it took it, the values and where it stopped.
struct SymbolReading {
  bool ok = false;
  std::vector<uint32_t> values;
  size_t end = 0;
};

/// draco::DecodeSymbols on bytes [0, size) from `at`, as the sequential decoder calls it.
inline SymbolReading draco_symbols(const uint8_t* data, size_t size, size_t at, uint32_t count,
                                   uint32_t components) {
  draco::DecoderBuffer in;
  in.Init(reinterpret_cast<const char*>(data), size, draco::kDracoMeshBitstreamVersion);
  in.StartDecodingFrom(int64_t(at));
  SymbolReading r;
  r.values.resize(count);
  r.ok = draco::DecodeSymbols(count, int(components), &in, r.values.data());
  r.end = size_t(in.decoded_size());
  return r;
}

/// The port's room for any table: rans_symbol_room of the bytes, and the buckets.
struct SymbolRoom {
  std::vector<wire::detail::RansSymbol> symbols;
  std::vector<uint32_t> buckets = std::vector<uint32_t>(wire::detail::kRansBuckets);
  wire::detail::RansSpace space(size_t bytes) {
    symbols.resize(wire::detail::rans_symbol_room(bytes, wire::detail::kRansMaxPrecisionBits));
    return {symbols.data(), static_cast<uint32_t>(symbols.size()), buckets.data()};
  }
};

/// The port on the same bytes. `room_ok` is false when it ran out of room (never expected).
inline SymbolReading port_symbols(const uint8_t* data, size_t size, size_t at, uint32_t count,
                                  uint32_t components, SymbolRoom& room, bool* room_ok = nullptr) {
  wire::detail::ByteReader in{data, size, at};
  SymbolReading r;
  r.values.resize(count);
  const auto s = wire::detail::decode_symbols(in, count, components, room.space(size - at), r.values.data());
  r.ok = s == wire::detail::SymbolStatus::kOk;
  if (room_ok) *room_ok = s != wire::detail::SymbolStatus::kNoRoom;
  r.end = in.pos;
  return r;
}

/// Both decoders on `data` from `at`: "" when they agree (both refuse, or both take the stream
/// with the same values and stop at the same byte), else what differs. `draco_took` and
/// `draco_end` (nullable) get whether Draco took it and where it stopped.
inline std::string compare_symbol_readings(const uint8_t* data, size_t size, size_t at, uint32_t count,
                                           uint32_t components, SymbolRoom& room, bool* draco_took = nullptr,
                                           size_t* draco_end = nullptr) {
  const SymbolReading d = draco_symbols(data, size, at, count, components);
  bool room_ok = true;
  const SymbolReading p = port_symbols(data, size, at, count, components, room, &room_ok);
  if (draco_took) *draco_took = d.ok;
  if (draco_end) *draco_end = d.end;
  if (!room_ok) return "the port ran out of room";
  if (d.ok != p.ok)
    return d.ok ? "Draco takes it, the port refuses it" : "the port takes it, Draco refuses it";
  if (!d.ok) return "";
  if (d.end != p.end)
    return "Draco stops at byte " + std::to_string(d.end) + ", the port at " + std::to_string(p.end);
  const auto m = std::mismatch(d.values.begin(), d.values.end(), p.values.begin());
  if (m.first == d.values.end()) return "";
  return "value " + std::to_string(m.first - d.values.begin()) + " is " + std::to_string(*m.second) +
         ", Draco's " + std::to_string(*m.first);
}

}  // namespace fq::test_wire
