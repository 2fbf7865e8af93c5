// The device decode of sequential chunks: a team per chunk (a block, a warp, or one thread,
// chunk_team.cuh) widens the connectivity indices, decodes the symbols with
// wire/symbol_decode.h, undoes the delta prediction and the wrap (wire/sequential_values.h) and
// dequantizes. The rANS stream is one chain of states, so one lane decodes it; everything
// around it (the tables' lookup, the tagged scheme's bits, the indices, the corrections, the
// dequantization) is spread over the lanes, a block's many warps keeping many loads in flight.
#include <cstring>

#include "kernels/cuda/chunk_decode.cuh"
#include "kernels/cuda/chunk_team.cuh"
#include "kernels/cuda/launch.cuh"
#include "wire/sequential_values.h"
#include "wire/symbol_decode.h"
#include "wire/varint.h"

namespace fq::cuda {
namespace {

using wire::detail::ByteReader;
using wire::detail::RansSpace;
using wire::detail::SymbolStatus;
using wire::detail::SymbolStream;
using wire::detail::WrapBounds;

/// (a + b) mod m for a, b < m < 2^31.
__device__ uint32_t add_mod(uint32_t a, uint32_t b, uint32_t m) {
  const uint32_t s = a + b;
  return s >= m ? s - m : s;
}

struct Plus {
  template <class V>
  __device__ V operator()(V a, V b) const {
    return a + b;
  }
};

/// Reads the chunk's 3 * faces indices (each below `points`, else kCornerOutOfRange) into out.
template <int T>
__device__ uint32_t widen_corners(const Team<T>& team, const ChunkJob& job, const uint8_t* bytes,
                                  uint32_t* out) {
  const uint8_t* p = bytes + job.corners_at;
  const uint64_t corners = 3 * uint64_t(job.faces);
  bool bad = false;
  if (job.index_bytes != 0) {
    for (uint64_t k = team.lane; k < corners; k += T) {
      uint32_t v = 0;
      for (unsigned b = 0; b < job.index_bytes; ++b) v |= uint32_t(p[k * job.index_bytes + b]) << (8 * b);
      out[k] = v;
      bad |= v >= job.points;
    }
  } else if constexpr (T == 1) {
    size_t pos = 0;
    const size_t n = job.corners_end - job.corners_at;
    for (uint64_t k = 0; k < corners; ++k) {
      uint32_t v = 0;
      wire::detail::get_varint(p, n, pos, v, 3);  // the host checked every varint
      out[k] = v;
      bad |= v >= job.points;
    }
  } else {
    // Varints of at most 3 bytes (the host checked them): each ends at a byte below 0x80, so a
    // team reads T bytes at once and numbers the ends by a scan.
    const uint32_t n = job.corners_end - job.corners_at;
    uint64_t first = 0;
    for (uint32_t base = 0; base < n; base += T) {
      const uint32_t i = base + team.lane;
      const bool ends = i < n && (p[i] & 0x80) == 0;
      uint32_t ends_here = 0;
      const uint32_t rank = team.scan(ends ? 1u : 0u, Plus{}, ends_here);
      if (ends) {
        uint32_t v = p[i];
        if (i >= 1 && (p[i - 1] & 0x80) != 0) {
          v = (v << 7) | (p[i - 1] & 0x7fu);
          if (i >= 2 && (p[i - 2] & 0x80) != 0) v = (v << 7) | (p[i - 2] & 0x7fu);
        }
        out[first + rank - 1] = v;
        bad |= v >= job.points;
      }
      first += ends_here;
    }
  }
  return team.any(bad) ? kCornerOutOfRange : kChunkDecoded;
}

/// Where a team keeps a table's lookup, and its symbols when they fit (a warp: in shared memory).
struct TableRoom {
  uint32_t* buckets;
  wire::detail::RansSymbol* fast = nullptr;  ///< room for `fast_capacity` symbols closer than the plan's
  uint32_t fast_capacity = 0;
};

/// The tagged scheme's values after its lengths (wire::detail::read_tagged_bits) by the team:
/// each group's bits start where the lengths before it put them (a scan), short of the end.
template <int T>
__device__ void team_tagged_bits(const Team<T>& team, ByteReader& in, uint32_t n, uint32_t components,
                                 uint32_t* out) {
  if constexpr (T == 1) {
    wire::detail::read_tagged_bits(in, n, components, out);
  } else {
    ByteReader at = in;
    team.share(at);
    const uint8_t* data = at.data + at.pos;
    const uint64_t bits = 8 * uint64_t(at.remaining());
    const uint32_t groups = n / components;
    uint64_t first = 0;
    for (uint32_t base = 0; base < groups; base += T) {
      const uint32_t g = base + team.lane;
      const uint32_t length = g < groups ? out[size_t(g) * components] : 0;
      uint64_t tile = 0;
      const uint64_t end = team.scan(uint64_t(length) * components, Plus{}, tile);
      if (g < groups) {
        uint64_t offset = first + end - uint64_t(length) * components;
        for (uint32_t j = 0; j < components; ++j, offset += length)
          out[size_t(g) * components + j] =
              wire::detail::bits_at(data, bits, offset < bits ? offset : bits, length);
      }
      first += tile;
    }
    if (team.is_first()) in.pos += size_t(((first < bits ? first : bits) + 7) / 8);
    team.sync();
  }
}

/// draco::DecodeSymbols by the team: the first lane reads the table (into the plan's room, then
/// closer where it fits) and the rANS stream, all lanes fill the lookup and read the tagged
/// scheme's bits. Only the first lane's `in` moves.
template <int T>
__device__ SymbolStatus team_symbols(const Team<T>& team, ByteReader& in, uint32_t n, uint32_t components,
                                     RansSpace space, const TableRoom& room, uint32_t* out) {
  SymbolStream s;
  uint32_t status = 0;
  if (team.is_first()) status = uint32_t(wire::detail::start_symbols(in, n, components, space, s));
  team.share(status);
  if (status != 0 || n == 0) return SymbolStatus(status);
  team.share(s);
  team.sync();  // the first lane's table, to every lane (shuffles do not order memory; __syncwarp does)
  if (s.table.count <= room.fast_capacity) {
    for (uint32_t k = team.lane; k < s.table.count; k += T) room.fast[k] = s.table.symbols[k];
    s.table.symbols = room.fast;
    team.sync();
  }
  wire::detail::fill_rans_buckets(s.table, team.lane, T);
  team.sync();
  if (s.scheme == wire::detail::kSymbolCodingTagged) {
    if (team.is_first()) status = uint32_t(wire::detail::read_tags(s.table, s.reader, n, components, out));
    team.share(status);
    team.sync();
    if (status == 0) team_tagged_bits(team, in, n, components, out);
  } else if (team.is_first()) {
    status = uint32_t(wire::detail::read_symbols(in, s, n, components, out));
  }
  team.share(status);
  team.sync();
  return SymbolStatus(status);
}

/// wire::detail::unwrap_values by the team. Where every correction is within [-dif, dif] and
/// no sum leaves int32 (Draco's own streams), each value is lo + (the corrections' sum mod
/// max_dif) from its start, which a warp scans; otherwise the first lane runs Draco's loop.
template <int T>
__device__ void team_unwrap(const Team<T>& team, int32_t* v, uint32_t points, uint32_t components,
                            const WrapBounds& w) {
  const size_t count = size_t(points) * components;
  if constexpr (T > 1) {
    const int64_t dif = int64_t(w.hi) - int64_t(w.lo);
    bool irregular = int64_t(w.lo) - dif < INT32_MIN || int64_t(w.hi) + dif > INT32_MAX;
    for (size_t i = team.lane; i < count && !irregular; i += T)
      irregular = uint64_t(uint32_t(v[i])) > 2 * uint64_t(dif);
    if (!team.any(irregular)) {
      const int32_t start = 0 > w.hi ? w.hi : (0 < w.lo ? w.lo : 0);
      const auto mod = [m = w.max_dif](uint32_t x, uint32_t y) { return add_mod(x, y, m); };
      for (uint32_t a = 0; a < components; ++a) {  // each component its own chain
        uint32_t carry = uint32_t(int64_t(start) - int64_t(w.lo));
        for (uint32_t base = 0; base < points; base += T) {
          const uint32_t p = base + team.lane;
          uint32_t c = 0;
          if (p < points) {
            const uint32_t s = uint32_t(v[size_t(p) * components + a]);
            c = (s & 1) ? w.max_dif - (s >> 1) - 1 : (s >> 1);  // the correction mod max_dif
          }
          uint32_t tile = 0;
          c = team.scan(c, mod, tile);
          if (p < points)
            v[size_t(p) * components + a] =
                static_cast<int32_t>(int64_t(w.lo) + add_mod(carry, c, w.max_dif));
          carry = add_mod(carry, tile, w.max_dif);
        }
      }
      team.sync();
      return;
    }
  }
  if (team.is_first()) wire::detail::unwrap_values(v, count, components, w);
  team.sync();
}

/// One attribute's values (the prediction's head, the symbols, the wrap) into v.
template <int T>
__device__ bool team_delta_values(const Team<T>& team, ByteReader& in, uint32_t points, uint32_t components,
                                  RansSpace space, const TableRoom& room, int32_t* v, bool& no_room) {
  uint32_t ok = 1;
  if (team.is_first()) ok = wire::detail::read_delta_head(in);
  team.share(ok);
  if (!ok) return false;
  const SymbolStatus s =
      team_symbols(team, in, points * components, components, space, room, reinterpret_cast<uint32_t*>(v));
  no_room = s == SymbolStatus::kNoRoom;
  if (s != SymbolStatus::kOk) return false;
  WrapBounds w;
  if (team.is_first()) ok = wire::detail::read_wrap_bounds(in, w);
  team.share(ok);
  if (!ok) return false;
  team.share(w);
  team_unwrap(team, v, points, components, w);
  return true;
}

template <int T>
__device__ uint32_t decode_chunk(const Team<T>& team, const ChunkDecodeArgs& a, const ChunkJob& job,
                                 const TableRoom& room) {
  const uint8_t* bytes = a.bytes + job.bytes_at;
  if (const uint32_t f = widen_corners(team, job, bytes, a.corners + job.first_corner); f != kChunkDecoded)
    return f;
  ByteReader in{bytes, job.size, job.values_at};
  const RansSpace space{a.symbols + job.symbols_at, job.symbol_room, room.buckets};
  int32_t* values = a.values + 3 * job.first_point;
  bool no_room = false;
  if (!team_delta_values(team, in, job.points, 3, space, room, values, no_room))
    return no_room ? kTableRoom : kPositionValues;
  if (job.labelled && !team_delta_values(team, in, job.points, 1, space, room,
                                         reinterpret_cast<int32_t*>(a.labels + job.first_point), no_room))
    return no_room ? kTableRoom : kLabelValues;
  wire::detail::Quantization q;
  uint32_t ok = 1;
  if (team.is_first()) ok = wire::detail::read_quantization(in, q);
  team.share(ok);
  if (!ok) return kQuantization;
  team.share(q);
  float* out = a.positions + 3 * job.first_point;
  for (size_t p = team.lane; p < job.points; p += T) {
#pragma unroll
    for (int axis = 0; axis < 3; ++axis)  // unrolled: q stays in registers
      out[3 * p + size_t(axis)] = wire::detail::dequantize(values[3 * p + size_t(axis)], q, axis);
  }
  return kChunkDecoded;
}

/// Symbols a team keeps in shared memory (12 KB; the lookup takes 16 KB more): every tagged
/// table (at most 33) and most raw ones of real chunks.
constexpr uint32_t kSharedSymbols = 1024;

/// A team of T > 1 threads a chunk, its lookup and (where they fit) its symbols in shared memory.
template <int T>
__global__ void __launch_bounds__(T) decode_chunks_by_team(ChunkDecodeArgs a) {
  __shared__ uint32_t buckets[wire::detail::kRansBuckets];
  __shared__ wire::detail::RansSymbol symbols[kSharedSymbols];
  __shared__ TeamScratch scratch;
  const Team<T> team{threadIdx.x, &scratch};
  const uint32_t chunk = blockIdx.x;
  const uint32_t fault = decode_chunk(team, a, a.jobs[chunk], TableRoom{buckets, symbols, kSharedSymbols});
  if (team.is_first()) a.faults[chunk] = fault;
}

/// A thread a chunk, its lookup in global memory.
__global__ void decode_chunks_by_thread(ChunkDecodeArgs a) {
  const uint64_t chunk = item_index();
  if (chunk >= a.chunks) return;
  const Team<1> team{0};
  a.faults[chunk] =
      decode_chunk(team, a, a.jobs[chunk], TableRoom{a.buckets + chunk * wire::detail::kRansBuckets});
}

}  // namespace

void launch_chunk_decode(const ChunkDecodeArgs& a, ChunkTeam team, cudaStream_t s) {
  if (a.chunks == 0) return;
  switch (team) {
    case ChunkTeam::kThread:
      // A warp of chunks a block, so that the chunks spread over the multiprocessors.
      FQ_LAUNCH(decode_chunks_by_thread, launch_shape((a.chunks + 31) / 32, 32), s, a);
      break;
    case ChunkTeam::kWarp:
      FQ_LAUNCH(decode_chunks_by_team<32>, launch_shape(a.chunks, 32), s, a);
      break;
    case ChunkTeam::kBlock:
      FQ_LAUNCH(decode_chunks_by_team<256>, launch_shape(a.chunks, 256), s, a);
      break;
    case ChunkTeam::kWideBlock:
      FQ_LAUNCH(decode_chunks_by_team<1024>, launch_shape(a.chunks, 1024), s, a);
      break;
  }
}

const char* chunk_fault_name(uint32_t fault) {
  switch (fault) {
    case kChunkDecoded:
      return "decoded";
    case kCornerOutOfRange:
      return "a face names a point the chunk does not have";
    case kPositionValues:
      return "the positions' values do not decode";
    case kLabelValues:
      return "the labels' values do not decode";
    case kQuantization:
      return "the quantization's parameters do not read";
    case kTableRoom:
      return "a symbol table outgrew its room";
    default:
      return "unknown fault";
  }
}

}  // namespace fq::cuda
