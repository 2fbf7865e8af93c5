// Internals of the frame codec shared by encoder and decoder: the spatial split of a
// mesh into chunks, the frame's bounding box and a small chunk-parallel loop.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "core/mesh_view.h"

namespace fq::wire::detail {

/// Axis-aligned bounding box of the vertices.
struct Box {
  float lo[3] = {0, 0, 0};
  float hi[3] = {0, 0, 0};
  /// Largest side (the range of Draco's explicit quantization).
  float max_extent() const;
};

/// Axis-aligned bounding box of the vertices. With `valid`, the same pass also checks that
/// every coordinate is finite and every triangle's indices are below num_vertices, and sets
/// *valid to whether all are (the box means nothing when not; check_mesh then names the fault).
Box bounding_box(const fq::MeshView& mesh, int threads = 1, bool* valid = nullptr);

/// Consecutive triangles [first, first + count) of a frame.
struct TriangleRun {
  uint32_t first = 0, count = 0;
};

/// One part of the split: its triangles as runs in ascending order (the input order kept).
/// A chunk is built from its runs straight out of the frame's triangle array.
struct Part {
  std::vector<TriangleRun> runs;
  uint32_t triangles = 0;
};

/// The triangles of each of `chunks` parts: triangles ranked by the smallest Morton code of
/// their vertices (10 bits per axis on `box`; ties broken by triangle id, so the split is
/// deterministic) and cut into equal counts, so each part is a spatially coherent patch.
/// Within a part, triangles keep their input order. Runs on `threads` threads.
std::vector<Part> split_parts(const fq::MeshView& mesh, const Box& box, uint32_t chunks, int threads = 1);

/// Number of workers for_each_chunk uses: min(threads, count), at least 1.
size_t chunk_workers(size_t count, int threads);

/// Calls fn(i, w) for every i in [0, count) on the calling thread and the shared host pool,
/// at most chunk_workers(count, threads) at a time (inline when 1); w < chunk_workers() names
/// the worker, for per-worker scratch space.
/// fn must not throw and must write only the outputs of item i (and worker w's scratch).
void for_each_chunk(size_t count, int threads, const std::function<void(size_t, size_t)>& fn);

}  // namespace fq::wire::detail
