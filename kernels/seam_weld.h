// Coincident vertices filtered as one (docs/ALGORITHM.md, "Seams"). Capture frames and PLY/Draco
// exports duplicate a vertex wherever its texture coordinates or normals change (a UV or normal
// seam): the triangles on each side reference their own copy. Filtered apart, each copy sees only
// its side's triangles and the copies drift apart: the surface cracks. Engine::process finds the
// copies (twins), runs the frame on the mesh with each set of twins welded into one vertex and
// writes the result back in the frame's own order and count, every twin the same output.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/mesh_view.h"

namespace fq {

/// Finds a frame's twins, gives the engine the welded frame and spreads the welded result back.
/// Its buffers are kept (grow-only) for the next frame, like an engine's scratch.
class SeamWeld {
 public:
  /// Finds the vertices of `mesh` at the same position as an earlier one, on `threads` threads
  /// (the same answer for any count); returns how many there are (the vertices a weld merges
  /// away). Reads positions only: indices need not be checked yet.
  uint32_t find(const MeshView& mesh, int threads);
  /// The frame after find() returned > 0, each set of twins one vertex (at its first copy's
  /// place in the order); `mesh`'s indices must be in range (check_mesh). Valid until the next
  /// find() or weld().
  MeshView weld(const MeshView& mesh, int threads);
  /// Per-vertex values of the welded frame (`stride` a vertex) back in the input's order and
  /// count: every twin gets its welded vertex's values. Empty stays empty.
  template <class T>
  void spread(std::vector<T>& values, size_t stride) const;
  /// The link forest (FrameResult::link_parent, link_p) back in the input's order: a welded
  /// vertex's link is its first copy's, with the parent numbered as in the input; every other
  /// copy links to the first with proximity 1, so it joins it at every theta.
  void spread_links(std::vector<uint32_t>& parent, std::vector<float>& p) const;
  /// Gives back the buffers.
  void release() { *this = SeamWeld{}; }

 private:
  std::vector<uint32_t> offsets_;              ///< per chunk of vertices and partition: its next entry
  std::vector<uint32_t> partition_begin_;      ///< per partition: its first entry (n after the last)
  std::vector<uint64_t> entries_;              ///< the vertices by partition: hash bits, vertex
  std::vector<std::vector<uint32_t>> copies_;  ///< per group of partitions: (copy, first copy) pairs
  uint32_t twins_ = 0;                         ///< find()'s count
  std::vector<uint32_t> first_;                ///< per input vertex: the first vertex at its position
  std::vector<uint32_t> welded_;               ///< per input vertex: its vertex in the welded frame
  std::vector<uint32_t> input_of_;             ///< per welded vertex: its first input vertex
  std::vector<float> positions_;
  std::vector<uint32_t> triangles_;
};

template <class T>
void SeamWeld::spread(std::vector<T>& values, size_t stride) const {
  if (values.empty()) return;
  const size_t n = welded_.size();
  values.resize(stride * n);
  // In place from the back: a vertex's welded index is never above its input index, so what
  // is read has not been overwritten yet.
  for (size_t v = n; v-- > 0;) {
    for (size_t k = 0; k < stride; ++k) values[stride * v + k] = values[stride * size_t(welded_[v]) + k];
  }
}

}  // namespace fq
