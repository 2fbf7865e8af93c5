// Spatial split of a frame into chunks, and the chunk-parallel loop.
#include "proto/frame_split.h"

#include <algorithm>
#include <atomic>
#include <numeric>
#include <system_error>
#include <thread>

#include "kernels/parallel_for.h"

namespace fq::wire::detail {
namespace {

/// Spreads the low 10 bits of v so that two zero bits separate each (for 30-bit Morton codes).
uint32_t spread_bits(uint32_t v) {
  v &= 0x3ffu;
  v = (v | (v << 16)) & 0x030000ffu;
  v = (v | (v << 8)) & 0x0300f00fu;
  v = (v | (v << 4)) & 0x030c30c3u;
  v = (v | (v << 2)) & 0x09249249u;
  return v;
}

uint32_t morton_of_centroid(const fq::MeshView& mesh, uint32_t t, const Box& box, float scale) {
  uint32_t cell[3];
  for (int a = 0; a < 3; ++a) {
    float c = 0.f;
    for (int k = 0; k < 3; ++k) c += mesh.positions[3 * size_t(mesh.triangles[3 * size_t(t) + k]) + a];
    const float u = (c / 3.f - box.lo[a]) * scale;
    cell[a] = static_cast<uint32_t>(std::clamp(u, 0.f, 1023.f));
  }
  return spread_bits(cell[0]) | (spread_bits(cell[1]) << 1) | (spread_bits(cell[2]) << 2);
}

}  // namespace

float Box::max_extent() const { return std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]}); }

Box bounding_box(const fq::MeshView& mesh) {
  Box b;
  if (mesh.num_vertices == 0) return b;
  for (int a = 0; a < 3; ++a) b.lo[a] = b.hi[a] = mesh.positions[a];
  for (uint32_t v = 1; v < mesh.num_vertices; ++v) {
    for (int a = 0; a < 3; ++a) {
      b.lo[a] = std::min(b.lo[a], mesh.positions[3 * size_t(v) + a]);
      b.hi[a] = std::max(b.hi[a], mesh.positions[3 * size_t(v) + a]);
    }
  }
  return b;
}

namespace {

/// Puts into first[c], for every chunk c in (c0, c1), the smallest key of chunk c: chunk c holds
/// the keys of rank [n c / chunks, n (c + 1) / chunks). Recursive bisection with nth_element:
/// O(n log chunks), no full sort.
void find_chunk_starts(std::vector<uint64_t>& keys, size_t lo, size_t hi, uint32_t c0, uint32_t c1,
                       uint32_t chunks, std::vector<uint64_t>& first) {
  if (c1 - c0 < 2) return;
  const uint32_t cm = c0 + (c1 - c0) / 2;
  const size_t cut = keys.size() * cm / chunks;
  std::nth_element(keys.begin() + lo, keys.begin() + cut, keys.begin() + hi);
  first[cm] = keys[cut];
  find_chunk_starts(keys, lo, cut, c0, cm, chunks, first);
  find_chunk_starts(keys, cut, hi, cm, c1, chunks, first);
}

}  // namespace

std::vector<std::vector<uint32_t>> split_triangles(const fq::MeshView& mesh, const Box& box, uint32_t chunks,
                                                   int threads) {
  const uint32_t n = mesh.num_triangles;
  std::vector<std::vector<uint32_t>> parts(chunks);
  if (chunks <= 1) {
    parts[0].resize(n);
    std::iota(parts[0].begin(), parts[0].end(), 0u);
    return parts;
  }
  const float extent = box.max_extent();
  const float scale = extent > 0.f ? 1023.f / extent : 0.f;
  // (code, triangle) in one integer: keys are unique, so equal counts per chunk are exact and
  // the split is deterministic. Keys and parts are built on all codec threads: this runs
  // before the chunks can be encoded in parallel, so it is on every frame's critical path.
  std::vector<uint64_t> keys(n);
  fq::parallel_for(n, threads, [&](uint32_t t) {
    keys[t] = (uint64_t(morton_of_centroid(mesh, t, box, scale)) << 32) | t;
  }, 4096);
  std::vector<uint64_t> first(chunks, 0);
  std::vector<uint64_t> work = keys;
  find_chunk_starts(work, 0, n, 0, chunks, chunks, first);
  // Within a chunk, triangles keep the input order (usually coherent: good for Draco's
  // sequential coder, which stores indices in face order). One scan of the keys per chunk.
  fq::parallel_for(chunks, threads, [&](uint32_t c) {
    const uint64_t lo = first[c], hi = c + 1 < chunks ? first[c + 1] : ~uint64_t{0};
    parts[c].reserve(n / chunks + 1);
    for (uint32_t t = 0; t < n; ++t) {
      if (keys[t] >= lo && keys[t] < hi) parts[c].push_back(t);
    }
  }, 1);
  return parts;
}

size_t chunk_workers(size_t count, int threads) {
  return std::max<size_t>(1, std::min<size_t>(count, size_t(std::max(threads, 1))));
}

void for_each_chunk(size_t count, int threads, const std::function<void(size_t, size_t)>& fn) {
  const size_t workers = chunk_workers(count, threads);
  std::atomic<size_t> next{0};
  const auto work = [&](size_t w) {
    for (size_t i = next++; i < count; i = next++) fn(i, w);
  };
  // The calling thread is worker 0. If a thread cannot be started (resource limits), the
  // workers already running finish the items: slower, never a lost chunk or an exception.
  std::vector<std::thread> pool;
  pool.reserve(workers - 1);
  for (size_t w = 1; w < workers; ++w) {
    try {
      pool.emplace_back(work, w);
    } catch (const std::system_error&) {
      break;
    }
  }
  work(0);
  for (auto& t : pool) t.join();
}

}  // namespace fq::wire::detail
