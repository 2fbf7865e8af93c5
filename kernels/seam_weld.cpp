#include "kernels/seam_weld.h"

#include <algorithm>
#include <bit>
#include <numeric>
#include <utility>

#include "core/cancel_token.h"
#include "core/parallel_for.h"

namespace fq {

namespace {

// Twins are vertices whose coordinates are exactly equal. An export writes a seam's copies from
// one stored position, so its twins are bit-identical; a tolerance would also weld vertices that
// are only close (two sheets of a thin shell, the lips of a cut, dense scan samples), would
// depend on the frame's scale and would not be transitive (a chain of close vertices), and it
// would need a neighbour search. Equal floats are equal points: -0 and +0 are one key.
struct Key {
  uint32_t x, y, z;
  bool operator==(const Key&) const = default;
};

uint32_t coordinate_bits(float f) {
  const uint32_t u = std::bit_cast<uint32_t>(f);
  return u == 0x80000000u ? 0u : u;
}

Key key_of(const float* positions, uint32_t v) {
  const float* p = positions + 3 * size_t(v);
  return {coordinate_bits(p[0]), coordinate_bits(p[1]), coordinate_bits(p[2])};
}

// splitmix64's finalizer: quantized coordinates (a Draco frame's) leave their low mantissa bits
// zero, and every bit of the key must reach the slot and the fingerprint.
uint64_t mix(uint64_t h) {
  h = (h ^ (h >> 30)) * 0xbf58476d1ce4e5b9ull;
  h = (h ^ (h >> 27)) * 0x94d049bb133111ebull;
  return h ^ (h >> 31);
}

uint64_t hash_of(Key k) { return mix((uint64_t(k.x) << 32 | k.y) ^ mix(k.z)); }

// The search is a partitioned hash (as a radix-partitioned hash join): the vertices are first
// scattered by the hash's top bits into partitions of kPartitionSize to twice that, keeping their
// order, then each partition's twins are found in a table of at most 32 KiB, in the core's cache.
// On the shared 2-core development machine: igea (0.13M vertices) 1.2 ms, dragon (0.44M) 5 to
// 11 ms as the other work on the machine came and went, igea_x16 (2.1M) 22 ms; one table over
// the whole frame missed the cache on every vertex beyond igea's size (dragon 14, igea_x16 135 ms).
constexpr uint32_t kPartitionSize = 2048;

struct Partitions {
  int bits = 0;  ///< partitions: 1 << bits

  // One partition when fewer vertices than kPartitionSize.
  explicit Partitions(uint32_t vertices) {
    if (vertices >= kPartitionSize) bits = int(std::bit_width(vertices / kPartitionSize)) - 1;
  }
  uint32_t count() const { return 1u << bits; }
  uint32_t of(uint64_t h) const { return bits == 0 ? 0u : uint32_t(h >> (64 - bits)); }
};

// A partition's entry: the hash's low half (the slot and a fingerprint that spares most position
// reads) over the vertex.
uint64_t entry_of(uint64_t h, uint32_t v) { return h << 32 | v; }
uint32_t fingerprint_of(uint64_t entry) { return uint32_t(entry >> 32); }
uint32_t vertex_of(uint64_t entry) { return uint32_t(entry); }

// Appends (copy, first copy) for each vertex of `entries` (in input order) that repeats an
// earlier one's position; `table` is the caller's scratch.
void find_in_partition(const uint64_t* entries, uint32_t count, const float* positions,
                       std::vector<uint32_t>& table, std::vector<uint32_t>& copies) {
  const uint32_t size = std::bit_ceil(std::max(2 * count, 16u));
  table.assign(size, ~0u);  // entry numbers; ~0 is empty
  for (uint32_t e = 0; e < count; ++e) {
    // Positions are read only for equal fingerprints (twins, almost always): the other reads
    // would miss the cache, the entries of a partition lying all over the frame.
    for (uint32_t i = fingerprint_of(entries[e]) & (size - 1);; i = (i + 1) & (size - 1)) {
      const uint32_t other = table[i];
      if (other == ~0u) {
        table[i] = e;
        break;
      }
      if (fingerprint_of(entries[other]) == fingerprint_of(entries[e]) &&
          key_of(positions, vertex_of(entries[other])) == key_of(positions, vertex_of(entries[e]))) {
        copies.insert(copies.end(), {vertex_of(entries[e]), vertex_of(entries[other])});
        break;
      }
    }
  }
}

}  // namespace

uint32_t SeamWeld::find(const MeshView& mesh, int threads) {
  // weld() reads what every loop here writes: none may skip its chunks under an expired token
  // (the frame's cancel check comes after its runs).
  const CancelScope whole(nullptr);
  threads = threads_or_all(threads);
  const uint32_t n = mesh.num_vertices;
  const Partitions parts(n);
  const uint32_t chunks = fixed_chunks(n), P = parts.count();
  // Partition sizes per chunk of vertices (a row per chunk: chunks on two threads share no
  // cache line), then each (chunk, partition)'s first entry: the entries of a partition come in
  // chunk order, so in input order.
  offsets_.assign(size_t(chunks) * P, 0);
  partition_begin_.resize(P + 1);
  const auto chunk_end = [&](uint32_t c) {
    return uint32_t(std::min<uint64_t>(n, uint64_t(c + 1) * kFixedChunk));
  };
  parallel_for(
      chunks, threads,
      [&](uint32_t c) {
        for (uint32_t v = c * kFixedChunk; v < chunk_end(c); ++v)
          ++offsets_[size_t(c) * P + parts.of(hash_of(key_of(mesh.positions, v)))];
      },
      kOneChunkAtATime);
  uint32_t first = 0;
  for (uint32_t p = 0; p < P; ++p) {
    partition_begin_[p] = first;
    for (uint32_t c = 0; c < chunks; ++c) first += std::exchange(offsets_[size_t(c) * P + p], first);
  }
  partition_begin_[P] = n;
  entries_.resize(n);
  parallel_for(
      chunks, threads,
      [&](uint32_t c) {
        uint32_t* next = &offsets_[size_t(c) * P];
        for (uint32_t v = c * kFixedChunk; v < chunk_end(c); ++v) {
          const uint64_t h = hash_of(key_of(mesh.positions, v));
          entries_[next[parts.of(h)]++] = entry_of(h, v);
        }
      },
      kOneChunkAtATime);
  // Partitions in groups, one table each: as many groups as partitions up to 64.
  const uint32_t groups = std::min(P, 64u), per_group = P / groups;
  copies_.resize(groups);
  parallel_for(
      groups, threads,
      [&](uint32_t g) {
        std::vector<uint32_t> table;
        copies_[g].clear();
        for (uint32_t p = g * per_group; p < (g + 1) * per_group; ++p) {
          const uint32_t begin = partition_begin_[p];
          find_in_partition(entries_.data() + begin, partition_begin_[p + 1] - begin, mesh.positions, table,
                            copies_[g]);
        }
      },
      kOneChunkAtATime);
  size_t twins = 0;
  for (const std::vector<uint32_t>& c : copies_) twins += c.size() / 2;
  twins_ = uint32_t(twins);
  first_.clear();
  if (twins == 0) return 0;
  first_.resize(n);
  std::iota(first_.begin(), first_.end(), 0u);
  for (const std::vector<uint32_t>& c : copies_) {
    for (size_t i = 0; i < c.size(); i += 2) first_[c[i]] = c[i + 1];
  }
  return uint32_t(twins);
}

MeshView SeamWeld::weld(const MeshView& mesh, int threads) {
  const CancelScope whole(nullptr);  // the engine reads every triangle
  threads = threads_or_all(threads);
  const uint32_t n = mesh.num_vertices;
  welded_.resize(n);
  input_of_.resize(n - twins_);
  uint32_t w = 0;
  for (uint32_t v = 0; v < n; ++v) {
    if (first_[v] == v) input_of_[w] = v;
    welded_[v] = first_[v] == v ? w++ : welded_[first_[v]];  // first_[v] < v: numbered already
  }
  positions_.resize(3 * size_t(w));
  parallel_for(w, threads, [&](uint32_t u) {
    std::copy_n(mesh.positions + 3 * size_t(input_of_[u]), 3, &positions_[3 * size_t(u)]);
  });
  triangles_.resize(3 * size_t(mesh.num_triangles));
  parallel_for(mesh.num_triangles, threads, [&](uint32_t t) {
    for (size_t c = 3 * size_t(t); c < 3 * size_t(t) + 3; ++c) triangles_[c] = welded_[mesh.triangles[c]];
  });
  return {positions_.data(), w, triangles_.data(), mesh.num_triangles};
}

void SeamWeld::spread_links(std::vector<uint32_t>& parent, std::vector<float>& p) const {
  if (parent.empty()) return;
  const size_t n = welded_.size();
  parent.resize(n);
  p.resize(n);
  for (size_t v = n; v-- > 0;) {  // in place from the back, as spread()
    const uint32_t w = welded_[v];
    if (input_of_[w] == v) {
      parent[v] = input_of_[parent[w]];
      p[v] = p[w];
    } else {
      parent[v] = input_of_[w];
      p[v] = 1.f;
    }
  }
}

}  // namespace fq
