#include "kernels/frame_prep.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "kernels/parallel_for.h"

namespace fq {

namespace {

// Reductions run over fixed-size chunks whose partial results are combined in chunk
// order, so every sum is bit-identical for any thread count.
constexpr uint32_t kChunk = 1u << 15;
// Each chunk is one work item of parallel_for.
constexpr int kOneChunkAtATime = 1;

uint32_t chunks_of(uint64_t n) { return static_cast<uint32_t>((n + kChunk - 1) / kChunk); }

int resolve(int threads) { return threads > 0 ? threads : hardware_threads(); }

// First index in [0, n) failing `bad`, or n. Parallel scan for the common (valid) case,
// then a serial search of the first failing chunk for a deterministic message.
template <class Bad>
uint64_t first_bad(uint64_t n, int threads, Bad bad) {
  std::atomic<uint32_t> first_chunk{UINT32_MAX};
  parallel_for(chunks_of(n), resolve(threads), [&](uint32_t c) {
    const uint64_t end = std::min<uint64_t>(n, uint64_t(c + 1) * kChunk);
    // Branch-free over the chunk (the compiler vectorizes it): the valid case reads every item.
    uint32_t any = 0;
    for (uint64_t i = uint64_t(c) * kChunk; i < end; ++i) any |= static_cast<uint32_t>(bad(i));
    if (any == 0) return;
    uint32_t cur = first_chunk.load();
    while (c < cur && !first_chunk.compare_exchange_weak(cur, c)) {
    }
  }, kOneChunkAtATime);
  if (first_chunk == UINT32_MAX) return n;
  for (uint64_t i = uint64_t(first_chunk) * kChunk;; ++i) {
    if (bad(i)) return i;
  }
}

}  // namespace

Status mesh_faults(const MeshView& mesh, uint64_t bad_coordinate, uint64_t bad_index) {
  if (bad_coordinate != kNone)
    return invalid_input("vertex " + std::to_string(bad_coordinate / 3) + " has a non-finite coordinate");
  if (bad_index != kNone)
    return invalid_input("triangle " + std::to_string(bad_index / 3) + " references vertex " +
                         std::to_string(mesh.triangles[bad_index]) + " but the mesh has " +
                         std::to_string(mesh.num_vertices) + " vertices");
  return {};
}

Status check_mesh_counts(const MeshView& mesh) {
  if (mesh.num_vertices == 0) return invalid_input("mesh has no vertices");
  if (mesh.num_triangles == 0) return invalid_input("mesh has no triangles (point clouds are not supported)");
  return {};
}

uint64_t first_non_finite(const float* values, uint64_t count, int threads) {
  // An all-ones exponent is Inf or NaN; as an integer test the scan vectorizes.
  return first_bad(count, threads, [&](uint64_t k) {
    return (std::bit_cast<uint32_t>(values[k]) & 0x7f800000u) == 0x7f800000u;
  });
}

Status check_mesh(const MeshView& mesh, int threads) {
  if (Status s = check_mesh_counts(mesh); !s.ok()) return s;
  const uint64_t nc = uint64_t(mesh.num_vertices) * 3;
  const uint64_t ni = uint64_t(mesh.num_triangles) * 3;
  uint64_t bad_coordinate = first_non_finite(mesh.positions, nc, threads);
  uint64_t bad_index = kNone;
  if (bad_coordinate == nc) {
    bad_coordinate = kNone;
    bad_index = first_bad(ni, threads, [&](uint64_t k) { return mesh.triangles[k] >= mesh.num_vertices; });
    if (bad_index == ni) bad_index = kNone;
  }
  return mesh_faults(mesh, bad_coordinate, bad_index);
}

double mean_edge_length(const MeshView& mesh, int threads) {
  if (mesh.num_triangles == 0) return 0.0;
  std::vector<double> partial(chunks_of(mesh.num_triangles), 0.0);
  parallel_for(static_cast<uint32_t>(partial.size()), resolve(threads), [&](uint32_t c) {
    const uint32_t end = std::min<uint64_t>(mesh.num_triangles, uint64_t(c + 1) * kChunk);
    double sum = 0.0;
    for (uint32_t t = c * kChunk; t < end; ++t) {
      const uint32_t* tri = mesh.triangles + 3 * size_t(t);
      for (int e = 0; e < 3; ++e) {
        const float* a = mesh.positions + 3 * size_t(tri[e]);
        const float* b = mesh.positions + 3 * size_t(tri[(e + 1) % 3]);
        const double dx = double(a[0]) - b[0], dy = double(a[1]) - b[1], dz = double(a[2]) - b[2];
        sum += std::sqrt(dx * dx + dy * dy + dz * dz);
      }
    }
    partial[c] = sum;
  }, kOneChunkAtATime);
  double sum = 0.0;
  for (double s : partial) sum += s;
  return sum / (3.0 * mesh.num_triangles);
}

Status compute_normalization(const MeshView& mesh, Normalization& out, int threads) {
  // Min and max do not depend on the order of evaluation: per-chunk bounds are exact.
  struct Box {
    double lo[3], hi[3];
  };
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<Box> boxes(chunks_of(mesh.num_vertices), Box{{kInf, kInf, kInf}, {-kInf, -kInf, -kInf}});
  parallel_for(static_cast<uint32_t>(boxes.size()), resolve(threads), [&](uint32_t c) {
    const uint32_t end = std::min<uint64_t>(mesh.num_vertices, uint64_t(c + 1) * kChunk);
    Box& b = boxes[c];
    for (uint32_t i = c * kChunk; i < end; ++i) {
      for (int k = 0; k < 3; ++k) {
        b.lo[k] = std::min(b.lo[k], double(mesh.positions[3 * size_t(i) + k]));
        b.hi[k] = std::max(b.hi[k], double(mesh.positions[3 * size_t(i) + k]));
      }
    }
  }, kOneChunkAtATime);
  Box all{{kInf, kInf, kInf}, {-kInf, -kInf, -kInf}};
  for (const Box& b : boxes) {
    for (int k = 0; k < 3; ++k) {
      all.lo[k] = std::min(all.lo[k], b.lo[k]);
      all.hi[k] = std::max(all.hi[k], b.hi[k]);
    }
  }
  return normalization_from(all.lo, all.hi, mean_edge_length(mesh, threads), out);
}

Status normalization_from(const double lo[3], const double hi[3], double mean_edge, Normalization& out) {
  for (int k = 0; k < 3; ++k) out.center[k] = 0.5 * (lo[k] + hi[k]);
  out.mean_edge = mean_edge;
  if (!(out.mean_edge > 0.0) || !std::isfinite(out.mean_edge))
    return invalid_input("mesh is degenerate: every edge has zero length");
  double extent = 0.0;
  for (int k = 0; k < 3; ++k) extent = std::max(extent, hi[k] - lo[k]);
  if (!(extent / out.mean_edge <= kMaxExtentInEdges)) {
    // Four digits: the CUDA engine's mean edge can differ in its last bits (another
    // summation order), and both engines must print the same message.
    char span[32];
    std::snprintf(span, sizeof span, "%.4g", extent / out.mean_edge);
    return invalid_input(std::string("mesh spans ") + span +
                         " mean edge lengths (at most 1e6 supported): is there a far outlier vertex?");
  }
  return {};
}

}  // namespace fq
