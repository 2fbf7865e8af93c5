#include "core/mesh_checks.h"

#include <atomic>
#include <bit>
#include <string>

#include "core/parallel_for.h"

namespace fq {

namespace {

// First index in [0, n) failing `bad`, or n. Parallel scan for the common (valid) case,
// then a serial search of the first failing chunk for a deterministic message.
template <class Bad>
uint64_t first_bad(uint64_t n, int threads, Bad bad) {
  std::atomic<uint32_t> first_chunk{UINT32_MAX};
  parallel_for(
      fixed_chunks(n), threads_or_all(threads),
      [&](uint32_t c) {
        const uint64_t end = std::min<uint64_t>(n, uint64_t(c + 1) * kFixedChunk);
        // Branch-free over the chunk (the compiler vectorizes it): the valid case reads every item.
        uint32_t any = 0;
        for (uint64_t i = uint64_t(c) * kFixedChunk; i < end; ++i) any |= static_cast<uint32_t>(bad(i));
        if (any == 0) return;
        uint32_t cur = first_chunk.load();
        while (c < cur && !first_chunk.compare_exchange_weak(cur, c)) {
        }
      },
      kOneChunkAtATime);
  if (first_chunk == UINT32_MAX) return n;
  for (uint64_t i = uint64_t(first_chunk) * kFixedChunk;; ++i) {
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

}  // namespace fq
