// Spatial split of a frame into chunks, and the chunk-parallel loop.
#include "proto/frame_split.h"

#include <algorithm>
#include <array>

#include "common/thread_pool.h"
#include "kernels/parallel_for.h"

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

uint32_t morton_of_centroid(const fq::MeshView& mesh, uint32_t t, const Box& box, float scale) {
  const uint32_t* tri = mesh.triangles + 3 * size_t(t);
  const float* p[3] = {mesh.positions + 3 * size_t(tri[0]), mesh.positions + 3 * size_t(tri[1]),
                       mesh.positions + 3 * size_t(tri[2])};
  uint32_t code = 0;
  for (int a = 0; a < 3; ++a) {
    const float c = (p[0][a] + p[1][a]) + p[2][a];
    const float u = (c / 3.f - box.lo[a]) * scale;  // finite: check_mesh ran
    code |= kSpread[static_cast<uint32_t>(std::min(std::max(u, 0.f), 1023.f))] << a;
  }
  return code;
}

}  // namespace

float Box::max_extent() const { return std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]}); }

Box bounding_box(const fq::MeshView& mesh, int threads) {
  Box b;
  if (mesh.num_vertices == 0) return b;
  // Per block of vertices, on the codec threads; min and max do not depend on the order.
  constexpr uint32_t kBlock = 1u << 14;
  std::vector<Box> boxes((mesh.num_vertices + kBlock - 1) / kBlock);
  fq::parallel_for(static_cast<uint32_t>(boxes.size()), threads, [&](uint32_t k) {
    Box& bk = boxes[k];
    const uint32_t first = k * kBlock, end = std::min(mesh.num_vertices, first + kBlock);
    for (int a = 0; a < 3; ++a) bk.lo[a] = bk.hi[a] = mesh.positions[3 * size_t(first) + a];
    for (uint32_t v = first + 1; v < end; ++v) {
      for (int a = 0; a < 3; ++a) {
        bk.lo[a] = std::min(bk.lo[a], mesh.positions[3 * size_t(v) + a]);
        bk.hi[a] = std::max(bk.hi[a], mesh.positions[3 * size_t(v) + a]);
      }
    }
  }, 1);
  b = boxes[0];
  for (const Box& bk : boxes) {
    for (int a = 0; a < 3; ++a) {
      b.lo[a] = std::min(b.lo[a], bk.lo[a]);
      b.hi[a] = std::max(b.hi[a], bk.hi[a]);
    }
  }
  return b;
}

namespace {

/// Morton codes are bucketed by their top kBucketBits bits to find the cut keys without sorting.
/// 4096 buckets: few enough for a histogram per worker, while a cut's bucket holds a small share
/// of the triangles (a surface occupies a few hundred of the 16^3 cells).
constexpr int kBucketBits = 12;
constexpr uint32_t kBuckets = 1u << kBucketBits;
uint32_t bucket_of(uint32_t code) { return code >> (30 - kBucketBits); }
uint64_t key_of(const std::vector<uint32_t>& codes, uint32_t t) { return (uint64_t(codes[t]) << 32) | t; }

/// Triangles handed to a worker at a time by the split's passes.
constexpr size_t kSplitGrain = size_t(1) << 14;

/// first[c] for c in [1, chunks): the key of rank n c / chunks (keys are unique). A histogram of
/// the buckets locates each rank's bucket; only the keys of those buckets are sorted. Both
/// passes over the codes run on the codec threads (per-worker histograms and key lists); the
/// result does not depend on the thread count.
std::vector<uint64_t> chunk_starts(const std::vector<uint32_t>& codes, uint32_t chunks, int threads) {
  const auto n = static_cast<uint32_t>(codes.size());
  const size_t workers = size_t(std::max(threads, 1));
  std::vector<std::vector<uint32_t>> hist(workers, std::vector<uint32_t>(kBuckets, 0));
  fq::ThreadPool::shared().run(n, static_cast<int>(workers), [&](size_t begin, size_t end, size_t w) {
    uint32_t* h = hist[w].data();
    for (size_t t = begin; t < end; ++t) ++h[bucket_of(codes[t])];
  }, kSplitGrain);
  std::vector<uint32_t> start(kBuckets + 1, 0);
  for (uint32_t b = 0; b < kBuckets; ++b) {
    start[b + 1] = start[b];
    for (const auto& h : hist) start[b + 1] += h[b];
  }
  // The buckets holding a cut, each with the keys it holds.
  std::vector<int32_t> slot(kBuckets, -1);
  std::vector<uint32_t> cut_bucket(chunks, 0);
  size_t slots = 0;
  for (uint32_t c = 1; c < chunks; ++c) {
    const uint64_t rank = uint64_t(n) * c / chunks;
    const uint32_t b = static_cast<uint32_t>(std::upper_bound(start.begin(), start.end(), rank) - start.begin()) - 1;
    cut_bucket[c] = b;
    if (slot[b] < 0) slot[b] = static_cast<int32_t>(slots++);
  }
  std::vector<std::vector<std::vector<uint64_t>>> found(workers, std::vector<std::vector<uint64_t>>(slots));
  fq::ThreadPool::shared().run(n, static_cast<int>(workers), [&](size_t begin, size_t end, size_t w) {
    for (size_t t = begin; t < end; ++t) {
      if (const int32_t s = slot[bucket_of(codes[t])]; s >= 0)
        found[w][size_t(s)].push_back(key_of(codes, static_cast<uint32_t>(t)));
    }
  }, kSplitGrain);
  std::vector<std::vector<uint64_t>> cut_keys(slots);
  for (size_t k = 0; k < slots; ++k) {
    for (auto& f : found) cut_keys[k].insert(cut_keys[k].end(), f[k].begin(), f[k].end());
    std::sort(cut_keys[k].begin(), cut_keys[k].end());
  }
  std::vector<uint64_t> first(chunks, 0);
  for (uint32_t c = 1; c < chunks; ++c) {
    const uint32_t b = cut_bucket[c];
    first[c] = cut_keys[size_t(slot[b])][uint64_t(n) * c / chunks - start[b]];
  }
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

/// Where each triangle goes: its chunk, and for each block of kBlock triangles the first slot
/// of its triangles in every chunk, so that blocks fill the chunks in parallel and triangles
/// keep the input order within a chunk (usually coherent: good for Draco's sequential coder,
/// which stores indices in face order).
struct SplitPlan {
  static constexpr uint32_t kBlock = 1u << 14;  // igea: 17 blocks, enough for 16 threads
  uint32_t chunks = 0, blocks = 0;
  std::vector<uint8_t> chunk_of;  ///< per triangle
  std::vector<uint32_t> at;       ///< blocks x chunks first slots
  std::vector<uint32_t> sizes;    ///< triangles per chunk
};

SplitPlan plan_split(const fq::MeshView& mesh, const Box& box, uint32_t chunks, int threads) {
  const uint32_t n = mesh.num_triangles;
  SplitPlan p;
  p.chunks = chunks;
  p.blocks = (n + SplitPlan::kBlock - 1) / SplitPlan::kBlock;
  p.chunk_of.assign(n, 0);
  p.at.assign(size_t(p.blocks) * chunks, 0);
  p.sizes.assign(chunks, 0);
  if (chunks <= 1) {
    p.sizes[0] = n;
    for (uint32_t b = 0; b < p.blocks; ++b) p.at[b] = b * SplitPlan::kBlock;
    return p;
  }
  const float extent = box.max_extent();
  const float scale = extent > 0.f ? 1023.f / extent : 0.f;
  // Key of triangle t = (code, t) in one integer: keys are unique, so equal counts per chunk
  // are exact and the split is deterministic. This runs before the chunks can be encoded in
  // parallel, so it is on every frame's critical path: all codec threads work on it.
  std::vector<uint32_t> codes(n);
  fq::parallel_for(n, threads, [&](uint32_t t) { codes[t] = morton_of_centroid(mesh, t, box, scale); }, 4096);
  const std::vector<uint64_t> first = chunk_starts(codes, chunks, threads);
  const std::vector<uint16_t> bucket_chunk = bucket_chunks(first);
  fq::parallel_for(p.blocks, threads, [&](uint32_t b) {
    uint32_t* count = &p.at[size_t(b) * chunks];
    for (uint32_t t = b * SplitPlan::kBlock; t < std::min(n, (b + 1) * SplitPlan::kBlock); ++t) {
      uint32_t c = bucket_chunk[bucket_of(codes[t])];
      if (c == kMixed)
        c = static_cast<uint32_t>(std::upper_bound(first.begin() + 1, first.end(), key_of(codes, t)) - first.begin()) - 1;
      p.chunk_of[t] = static_cast<uint8_t>(c);
      ++count[c];
    }
  }, 1);
  for (uint32_t c = 0; c < chunks; ++c) {
    uint32_t offset = 0;  // counts become each block's first slot in chunk c
    for (uint32_t b = 0; b < p.blocks; ++b) {
      uint32_t& count = p.at[size_t(b) * chunks + c];
      const uint32_t own = count;
      count = offset;
      offset += own;
    }
    p.sizes[c] = offset;
  }
  return p;
}

/// Calls put(c, slot, t) for every triangle t: its chunk and its place there. Consumes p.at.
template <class Put>
void fill_split(const fq::MeshView& mesh, SplitPlan& p, int threads, Put put) {
  fq::parallel_for(p.blocks, threads, [&](uint32_t b) {
    uint32_t* at = &p.at[size_t(b) * p.chunks];
    for (uint32_t t = b * SplitPlan::kBlock; t < std::min(mesh.num_triangles, (b + 1) * SplitPlan::kBlock); ++t)
      put(p.chunk_of[t], at[p.chunk_of[t]]++, t);
  }, 1);
}

}  // namespace

std::vector<std::vector<uint32_t>> split_triangles(const fq::MeshView& mesh, const Box& box, uint32_t chunks,
                                                   int threads) {
  SplitPlan p = plan_split(mesh, box, chunks, threads);
  std::vector<std::vector<uint32_t>> parts(chunks);
  for (uint32_t c = 0; c < chunks; ++c) parts[c].resize(p.sizes[c]);
  fill_split(mesh, p, threads, [&](uint32_t c, uint32_t slot, uint32_t t) { parts[c][slot] = t; });
  return parts;
}

std::vector<PartCorners> split_corners(const fq::MeshView& mesh, const Box& box, uint32_t chunks, int threads) {
  SplitPlan p = plan_split(mesh, box, chunks, threads);
  std::vector<PartCorners> parts(chunks);
  for (uint32_t c = 0; c < chunks; ++c) {
    parts[c].size = 3 * size_t(p.sizes[c]);
    parts[c].data.reset(new uint32_t[parts[c].size]);  // every slot is written by fill_split
  }
  // The frame's triangles are read in order here, so building a chunk reads only its own.
  fill_split(mesh, p, threads, [&](uint32_t c, uint32_t slot, uint32_t t) {
    const uint32_t* in = mesh.triangles + 3 * size_t(t);
    uint32_t* out = parts[c].data.get() + 3 * size_t(slot);
    out[0] = in[0];  // three stores, not a memmove call per triangle
    out[1] = in[1];
    out[2] = in[2];
  });
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
