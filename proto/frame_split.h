// Internals of the frame codec shared by encoder and decoder: the spatial split of a
// mesh into chunks, the frame's bounding box and a small chunk-parallel loop.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "kernels/mesh_view.h"

namespace fq::wire::detail {

/// Axis-aligned bounding box of the vertices.
struct Box {
  float lo[3] = {0, 0, 0};
  float hi[3] = {0, 0, 0};
  /// Largest side (the range of Draco's explicit quantization).
  float max_extent() const;
};

Box bounding_box(const fq::MeshView& mesh, int threads = 1);

/// Triangle ids of each of `chunks` parts: triangles ranked by the Morton code of their
/// centroid (10 bits per axis on `box`; ties broken by triangle id, so the split is
/// deterministic) and cut into equal counts, so each part is a spatially coherent patch.
/// Within a part, triangles keep their input order. Runs on `threads` threads.
std::vector<std::vector<uint32_t>> split_triangles(const fq::MeshView& mesh, const Box& box, uint32_t chunks,
                                                   int threads = 1);

/// The corners (3 vertex ids per triangle) of one part's triangles. Not zero-filled before
/// the split writes them: that would be a serial pass over the whole frame.
struct PartCorners {
  std::unique_ptr<uint32_t[]> data;
  size_t size = 0;
  std::span<const uint32_t> span() const { return {data.get(), size}; }
};

/// The same split as split_triangles, as the corners of each part's triangles: what a chunk
/// is built from.
std::vector<PartCorners> split_corners(const fq::MeshView& mesh, const Box& box, uint32_t chunks, int threads = 1);

/// Number of workers for_each_chunk uses: min(threads, count), at least 1.
size_t chunk_workers(size_t count, int threads);

/// Calls fn(i, w) for every i in [0, count) on the calling thread and the shared host pool,
/// at most chunk_workers(count, threads) at a time (inline when 1); w < chunk_workers() names
/// the worker, for per-worker scratch space.
/// fn must not throw and must write only the outputs of item i (and worker w's scratch).
void for_each_chunk(size_t count, int threads, const std::function<void(size_t, size_t)>& fn);

}  // namespace fq::wire::detail
