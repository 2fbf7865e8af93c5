// Connected clusters. Quick shift links a vertex to any better-ranked vertex within 2 sigma_d
// in space, not along the surface, so one label can cover pieces that do not touch (the
// paper's stated limitation). This step splits every label into its mesh-connected parts and
// merges parts that are too small to be features into the neighbour they share most edges with.
#pragma once

#include <cstdint>
#include <vector>

#include "core/mesh_view.h"

namespace fq {

/// Relabels `labels` (one per vertex of `mesh`) so that every label is one edge-connected
/// set of vertices and, where a neighbour exists, has at least `min_size` vertices. Labels
/// are numbered 0..K-1 by their smallest vertex index; returns K. min_size <= 1 only splits.
uint32_t connect_clusters(const MeshView& mesh, std::vector<uint32_t>& labels, uint32_t min_size);

}  // namespace fq
