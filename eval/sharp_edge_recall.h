// Does a clustering follow the features? The share of a clean mesh's sharp-edge length
// across which the labels change: a cluster boundary that runs along every crease gives 1,
// one cluster for the whole mesh gives 0. Blind to over-segmentation (one label per vertex
// also gives 1), so it is always read next to the cluster count.
#pragma once

#include <cstdint>

#include "core/mesh_view.h"

namespace fq {

struct SharpEdgeRecall {
  double recall = 0.0;        ///< separated_length / sharp_length; NaN when there is no sharp edge
  double sharp_length = 0.0;  ///< total length of the sharp edges, in the mesh's units
  double separated_length = 0.0;
  uint32_t sharp_edges = 0;
  uint32_t separated_edges = 0;
};

/// Default crease threshold: the angle between the two face normals of an edge.
inline constexpr double kSharpEdgeDegrees = 30.0;

/// Over the edges of `clean` shared by exactly two non-degenerate triangles whose normals
/// differ by more than `min_angle_deg` (sharp edges), the length-weighted share whose two
/// opposite vertices (the third vertex of each triangle) carry different labels. The
/// opposite vertices rather than the edge's endpoints: a vertex on a crease belongs to
/// both sides, the vertices beside it to one each. `labels` holds one label per vertex of
/// `clean` (any clustering of a mesh with the same vertices, e.g. a noisy copy).
SharpEdgeRecall sharp_edge_recall(const MeshView& clean, const uint32_t* labels,
                                  double min_angle_deg = kSharpEdgeDegrees);

}  // namespace fq
