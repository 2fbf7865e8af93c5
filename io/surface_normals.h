// Normals of a filtered surface, for the files that carry normals: a filter moves positions,
// and normals left as they were make the result look unsmoothed in every viewer.
#pragma once

#include <array>
#include <vector>

#include "core/mesh_view.h"
#include "io/mesh_attributes.h"

namespace fq::io {

/// The area-weighted unit normal of every vertex of `mesh` (the mean of its triangles'
/// normals, larger triangles weighing more); zero for a vertex on no non-degenerate triangle.
std::vector<std::array<float, 3>> vertex_normals(const MeshView& mesh);

/// Overwrites the nx, ny, nz vertex properties (when all three are there) with vertex_normals
/// of `mesh`. A vertex on no non-degenerate triangle keeps its old normal. Returns whether it did.
bool recompute_normals(const MeshView& mesh, MeshAttributes& attributes);

/// Recomputes per-corner normals (an OBJ's `vn`) for the surface `mesh`, keeping the input's
/// hard edges: at each vertex, the corners that carried the same normal (same value) form a
/// group, and the group's new normal is the area-weighted normal of its corners' triangles.
/// A group on degenerate triangles only keeps its old normal. Does nothing when `normals`
/// is empty.
void recompute_corner_normals(const MeshView& mesh, CornerValues& normals);

}  // namespace fq::io
