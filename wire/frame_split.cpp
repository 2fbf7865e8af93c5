// Spatial split of a frame into chunks, and the chunk-parallel loop.
#include "wire/frame_split.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <memory>

#include "common/thread_pool.h"
#include "core/parallel_for.h"

namespace fq::wire::detail {
namespace {

/// Spreads the low 10 bits of v so that two zero bits separate each (for 30-bit Morton codes).
constexpr uint32_t spread_bits(uint32_t v) {
  v &= 0x3ffu;
  v = (v | (v << 16)) & 0x030000ffu;
  v = (v | (v << 8)) & 0x0300f00fu;
  v = (v | (v << 4)) & 0x030c30c3u;
  v = (v | (v << 2)) & 0x09249249u;
  return v;
}

/// spread_bits of every 10-bit cell: one load instead of a dozen operations per axis.
constexpr std::array<uint32_t, 1024> kSpread = [] {
  std::array<uint32_t, 1024> t{};
  for (uint32_t v = 0; v < 1024; ++v) t[v] = spread_bits(v);
  return t;
}();

/// n codes, not zero-filled: the pass that makes them writes every entry on the codec threads,
/// where a std::vector would first zero them all on one thread.
using Codes = std::unique_ptr<uint32_t[]>;

/// Morton code (10 bits per axis) of the cell of each vertex on the grid over `box`.
Codes vertex_codes(const fq::MeshView& mesh, const Box& box, int threads) {
  const float extent = box.max_extent();
  const float scale = extent > 0.f ? 1023.f / extent : 0.f;
  const float lo[3] = {box.lo[0], box.lo[1], box.lo[2]};
  Codes codes(new uint32_t[mesh.num_vertices]);
  uint32_t* out = codes.get();
  const float* positions = mesh.positions;
  fq::ThreadPool::shared().run(
      mesh.num_vertices, threads,
      [=](size_t begin, size_t end, size_t) {
        for (size_t v = begin; v < end; ++v) {
          uint32_t code = 0;
          for (int a = 0; a < 3; ++a) {
            const float u =
                (positions[3 * v + size_t(a)] - lo[a]) * scale;  // finite: checked by the box pass
            code |= kSpread[static_cast<uint32_t>(std::min(std::max(u, 0.f), 1023.f))] << a;
          }
          out[v] = code;
        }
      },
      size_t(1) << 14);
  return codes;
}

}  // namespace

float Box::max_extent() const { return std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]}); }

namespace {

/// Four floats or ints as one value (GCC and Clang vector extensions, on any target): the
/// compiler does not vectorize the three interleaved axes of a min/max loop by itself.
using Float4 = float __attribute__((vector_size(16)));
using Int4 = int32_t __attribute__((vector_size(16)));

/// Box of vertices [first, end); sets `bad` when a coordinate is Inf or NaN. Twelve floats (four
/// vertices) at a time as three Float4, so lane j of vector k holds axis (4 k + j) % 3. The
/// block's first vertex seeds every lane of its axis.
Box block_box(const float* positions, uint32_t first, uint32_t end, bool& bad) {
  const float* p = positions + 3 * size_t(first);
  float seed[12];
  for (int j = 0; j < 12; ++j) seed[j] = p[j % 3];
  Float4 lo[3], hi[3];
  std::memcpy(lo, seed, sizeof(seed));
  std::memcpy(hi, seed, sizeof(seed));
  Int4 exponent_ones = {0, 0, 0, 0};
  const Int4 mask = {0x7f800000, 0x7f800000, 0x7f800000, 0x7f800000};
  const size_t floats = 3 * size_t(end - first), whole = floats / 12 * 12;
  for (size_t i = 0; i < whole; i += 12) {
    for (int k = 0; k < 3; ++k) {
      Float4 x;
      std::memcpy(&x, p + i + 4 * size_t(k), sizeof(x));
      lo[k] = x < lo[k] ? x : lo[k];
      hi[k] = x > hi[k] ? x : hi[k];
      Int4 bits;
      std::memcpy(&bits, &x, sizeof(bits));
      exponent_ones |= (bits & mask) == mask;  // -1 where Inf or NaN
    }
  }
  float lo_lanes[12], hi_lanes[12];
  std::memcpy(lo_lanes, lo, sizeof(lo_lanes));
  std::memcpy(hi_lanes, hi, sizeof(hi_lanes));
  bool non_finite =
      exponent_ones[0] != 0 || exponent_ones[1] != 0 || exponent_ones[2] != 0 || exponent_ones[3] != 0;
  for (size_t i = whole; i < floats; ++i) {
    lo_lanes[i % 3] = std::min(lo_lanes[i % 3], p[i]);
    hi_lanes[i % 3] = std::max(hi_lanes[i % 3], p[i]);
    non_finite |= !std::isfinite(p[i]);
  }
  bad = non_finite;
  Box box;
  for (int a = 0; a < 3; ++a) {
    box.lo[a] = std::min({lo_lanes[a], lo_lanes[a + 3], lo_lanes[a + 6], lo_lanes[a + 9]});
    box.hi[a] = std::max({hi_lanes[a], hi_lanes[a + 3], hi_lanes[a + 6], hi_lanes[a + 9]});
  }
  return box;
}

/// Whether a corner in [first, end) names a vertex at or past `n` (branch-free: it vectorizes).
bool bad_corner(const uint32_t* corners, size_t first, size_t end, uint32_t n) {
  uint32_t bad = 0;
  for (size_t i = first; i < end; ++i) bad |= static_cast<uint32_t>(corners[i] >= n);
  return bad != 0;
}

}  // namespace

Box bounding_box(const fq::MeshView& mesh, int threads, bool* valid) {
  Box b;
  if (valid != nullptr) *valid = mesh.num_vertices > 0;
  if (mesh.num_vertices == 0) return b;
  // One dispatch on the codec threads: blocks of vertices (box, finite coordinates) and, when
  // checking, blocks of corners (indices); min and max do not depend on the order.
  constexpr uint32_t kBlock = 1u << 14;
  const size_t vertex_blocks = (size_t(mesh.num_vertices) + kBlock - 1) / kBlock;
  const size_t corners = valid != nullptr ? 3 * size_t(mesh.num_triangles) : 0;
  constexpr size_t kCornerBlock = 4 * size_t(kBlock);
  const size_t corner_blocks = (corners + kCornerBlock - 1) / kCornerBlock;
  std::vector<Box> boxes(vertex_blocks);
  std::vector<uint8_t> bad(vertex_blocks + corner_blocks, 0);
  fq::ThreadPool::shared().run(vertex_blocks + corner_blocks, threads, [&](size_t begin, size_t end, size_t) {
    for (size_t k = begin; k < end; ++k) {
      if (k < vertex_blocks) {
        const auto first = static_cast<uint32_t>(k * kBlock);
        bool b_bad = false;
        boxes[k] = block_box(mesh.positions, first, std::min(mesh.num_vertices, first + kBlock), b_bad);
        bad[k] = b_bad;
      } else {
        const size_t first = (k - vertex_blocks) * kCornerBlock;
        bad[k] =
            bad_corner(mesh.triangles, first, std::min(corners, first + kCornerBlock), mesh.num_vertices);
      }
    }
  });
  b = boxes[0];
  for (const Box& bk : boxes) {
    for (int a = 0; a < 3; ++a) {
      b.lo[a] = std::min(b.lo[a], bk.lo[a]);
      b.hi[a] = std::max(b.hi[a], bk.hi[a]);
    }
  }
  if (valid != nullptr) *valid = std::find(bad.begin(), bad.end(), uint8_t{1}) == bad.end();
  return b;
}

namespace {

/// Keys are bucketed by their codes' top kBucketBits bits to find the cut keys without sorting.
/// 4096 buckets: few enough for a histogram per worker, while a cut's bucket holds a small share
/// of the triangles (a surface occupies a few hundred of the 16^3 cells).
constexpr int kBucketBits = 12;
constexpr uint32_t kBuckets = 1u << kBucketBits;
uint32_t bucket_of(uint32_t code) { return code >> (30 - kBucketBits); }
uint64_t key_of(const uint32_t* codes, uint32_t t) { return (uint64_t(codes[t]) << 32) | t; }

/// Triangles handed to a worker at a time by the split's passes.
constexpr size_t kSplitGrain = size_t(1) << 14;

/// The key code of every triangle, the smallest Morton code of its three vertices, and the
/// histogram of their buckets. A triangle goes with its lowest vertex along the Morton curve:
/// that cuts fewer triangles' vertices apart than their centroids do (on the dragon, 1.5% of
/// the vertices repeated in two chunks against 1.7%; on igea 2.5% against 3.0%), and costs
/// three lookups of a per-vertex code instead of three positions and a quantization.
/// Per-worker histograms on the codec threads, added after. A coherent input puts runs of
/// triangles in one bucket: counting runs, not triangles, keeps the increments from waiting
/// on each other.
Codes triangle_codes(const fq::MeshView& mesh, const Box& box, int threads,
                     std::vector<uint32_t>& histogram) {
  const Codes vertex_code = vertex_codes(mesh, box, threads);
  const uint32_t* vcode = vertex_code.get();
  const uint32_t n = mesh.num_triangles;
  Codes codes(new uint32_t[n]);
  const size_t workers = size_t(std::max(threads, 1));
  std::vector<std::vector<uint32_t>> hist(workers, std::vector<uint32_t>(kBuckets, 0));
  fq::ThreadPool::shared().run(
      n, static_cast<int>(workers),
      [&](size_t begin, size_t end, size_t w) {
        uint32_t* h = hist[w].data();
        uint32_t run_bucket = 0, run = 0;
        for (size_t t = begin; t < end; ++t) {
          const uint32_t* tri = mesh.triangles + 3 * t;
          const uint32_t code = std::min({vcode[tri[0]], vcode[tri[1]], vcode[tri[2]]});
          codes[t] = code;
          const uint32_t b = bucket_of(code);
          if (b == run_bucket) {
            ++run;
            continue;
          }
          h[run_bucket] += run;
          run_bucket = b;
          run = 1;
        }
        h[run_bucket] += run;
      },
      kSplitGrain);
  histogram.assign(kBuckets, 0);
  for (const auto& hw : hist)
    for (uint32_t b = 0; b < kBuckets; ++b) histogram[b] += hw[b];
  return codes;
}

/// first[c] for c in [1, chunks): the key of rank n c / chunks (keys are unique). The bucket
/// histogram locates each rank's bucket; only the keys of those buckets are gathered (on the
/// codec threads, per-worker lists) and searched. The result does not depend on the thread count.
std::vector<uint64_t> chunk_starts(const uint32_t* codes, uint32_t n, const std::vector<uint32_t>& histogram,
                                   uint32_t chunks, int threads) {
  const size_t workers = size_t(std::max(threads, 1));
  std::vector<uint32_t> start(kBuckets + 1, 0);
  for (uint32_t b = 0; b < kBuckets; ++b) start[b + 1] = start[b] + histogram[b];
  // The buckets holding a cut, each with the keys it holds.
  std::vector<int32_t> slot(kBuckets, -1);
  std::vector<uint32_t> cut_bucket(chunks, 0);
  size_t slots = 0;
  for (uint32_t c = 1; c < chunks; ++c) {
    const uint64_t rank = uint64_t(n) * c / chunks;
    const uint32_t b =
        static_cast<uint32_t>(std::upper_bound(start.begin(), start.end(), rank) - start.begin()) - 1;
    cut_bucket[c] = b;
    if (slot[b] < 0) slot[b] = static_cast<int32_t>(slots++);
  }
  std::vector<std::vector<std::vector<uint64_t>>> found(workers, std::vector<std::vector<uint64_t>>(slots));
  fq::ThreadPool::shared().run(
      n, static_cast<int>(workers),
      [&](size_t begin, size_t end, size_t w) {
        for (size_t t = begin; t < end; ++t) {
          if (const int32_t s = slot[bucket_of(codes[t])]; s >= 0)
            found[w][size_t(s)].push_back(key_of(codes, static_cast<uint32_t>(t)));
        }
      },
      kSplitGrain);
  // Each cut's key by selection (nth_element) among its bucket's keys, the buckets on the codec
  // threads: a bucket holds thousands of keys, and sorting them one after the other was the
  // longest serial step of the split on 16 threads.
  std::vector<uint64_t> first(chunks, 0);
  for_each_chunk(slots, threads, [&](size_t k, size_t) {
    std::vector<uint64_t> keys;
    for (const auto& f : found) keys.insert(keys.end(), f[k].begin(), f[k].end());
    for (uint32_t c = 1; c < chunks; ++c) {
      const uint32_t b = cut_bucket[c];
      if (size_t(slot[b]) != k) continue;
      const auto nth = keys.begin() + std::ptrdiff_t(uint64_t(n) * c / chunks - start[b]);
      std::nth_element(keys.begin(), nth, keys.end());
      first[c] = *nth;
    }
  });
  return first;
}

/// Chunk of the triangles of each bucket (all of them fall in one chunk), or kMixed for a
/// bucket that holds a cut (its triangles need a binary search among the cuts).
constexpr uint16_t kMixed = 0xffff;
std::vector<uint16_t> bucket_chunks(const std::vector<uint64_t>& first) {
  const auto chunks = static_cast<uint32_t>(first.size());
  std::vector<uint16_t> out(kBuckets);
  uint32_t next = 1;  // the first cut not in an earlier bucket
  for (uint32_t b = 0; b < kBuckets; ++b) {
    const auto cut_here = [&] { return next < chunks && bucket_of(uint32_t(first[next] >> 32)) == b; };
    if (!cut_here()) {
      out[b] = static_cast<uint16_t>(next - 1);
      continue;
    }
    out[b] = kMixed;
    while (cut_here()) ++next;
  }
  return out;
}

/// A run of triangles of one chunk, as found by one block of the runs pass.
struct ChunkRun {
  uint32_t chunk, first, count;
};

/// Triangles handed to a worker at a time by the runs pass; igea has 17 such blocks, enough
/// for 16 threads.
constexpr uint32_t kRunBlock = 1u << 14;

/// Appends [first, first + count) to `part`, extending its last run when they touch.
void append_run(Part& part, uint32_t first, uint32_t count) {
  part.triangles += count;
  if (!part.runs.empty() && part.runs.back().first + part.runs.back().count == first) {
    part.runs.back().count += count;
    return;
  }
  part.runs.push_back({first, count});
}

}  // namespace

std::vector<Part> split_parts(const fq::MeshView& mesh, const Box& box, uint32_t chunks, int threads) {
  const uint32_t n = mesh.num_triangles;
  std::vector<Part> parts(std::max(chunks, 1u));
  if (chunks <= 1 || n == 0) {
    if (n > 0) append_run(parts[0], 0, n);
    return parts;
  }
  // Key of triangle t = (code, t) in one integer: keys are unique, so equal counts per chunk
  // are exact and the split is deterministic. This runs before the chunks can be encoded in
  // parallel, so it is on every frame's critical path: all codec threads work on it.
  std::vector<uint32_t> histogram;
  const Codes code_array = triangle_codes(mesh, box, threads, histogram);
  const uint32_t* codes = code_array.get();
  const std::vector<uint64_t> first = chunk_starts(codes, n, histogram, chunks, threads);
  const std::vector<uint16_t> bucket_chunk = bucket_chunks(first);
  const auto chunk_of = [&](uint32_t t) -> uint32_t {
    const uint32_t c = bucket_chunk[bucket_of(codes[t])];
    if (c != kMixed) return c;
    return static_cast<uint32_t>(std::upper_bound(first.begin() + 1, first.end(), key_of(codes, t)) -
                                 first.begin()) -
           1;
  };
  // Each block's triangles as runs of one chunk (a coherent input has long runs), then the
  // blocks' runs handed to their chunks in block order: triangles keep the input order within
  // a chunk (usually coherent: good for Draco's sequential coder, which stores indices in face
  // order), and a chunk is built straight from the frame's triangle array, with no copy.
  const uint32_t blocks = (n + kRunBlock - 1) / kRunBlock;
  std::vector<std::vector<ChunkRun>> block_runs(blocks);
  fq::parallel_for(
      blocks, threads,
      [&](uint32_t b) {
        std::vector<ChunkRun>& out = block_runs[b];
        const uint32_t begin = b * kRunBlock, end = std::min(n, begin + kRunBlock);
        uint32_t current = chunk_of(begin), run_first = begin;
        for (uint32_t t = begin + 1; t < end; ++t) {
          const uint32_t c = chunk_of(t);
          if (c == current) continue;
          out.push_back({current, run_first, t - run_first});
          current = c;
          run_first = t;
        }
        out.push_back({current, run_first, end - run_first});
      },
      1);
  for (const auto& runs : block_runs)
    for (const ChunkRun& r : runs) append_run(parts[r.chunk], r.first, r.count);
  return parts;
}

size_t chunk_workers(size_t count, int threads) {
  return std::max<size_t>(1, std::min<size_t>(count, size_t(std::max(threads, 1))));
}

void for_each_chunk(size_t count, int threads, const std::function<void(size_t, size_t)>& fn) {
  // On the shared host pool: no thread is created per frame, and concurrent frames (fqd's
  // decode and encode workers) share the pool's threads instead of each starting their own.
  fq::ThreadPool::shared().run(count, static_cast<int>(chunk_workers(count, threads)),
                               [&fn](size_t begin, size_t end, size_t w) {
                                 for (size_t i = begin; i < end; ++i) fn(i, w);
                               });
}

}  // namespace fq::wire::detail
