// The closest point of a triangle mesh to a query point, exactly, through a grid of the
// triangles' centroids: eval/surface_distance.cpp (vertex to surface) and eval/scan_error.cpp
// (a scan's faces against a reconstruction) search the same way.
#pragma once

#include <cstdint>
#include <vector>

#include "core/mesh_view.h"
#include "kernels/grid_build.h"
#include "kernels/vec3.h"

namespace fq {

/// Double-precision point; the index works in doubles so that distances far below the
/// mesh's scale (a filtered scan against its reconstruction) keep their digits.
struct Point3d {
  double x, y, z;
};

/// The closest point of the mesh and the triangle it lies on; triangle is UINT32_MAX and
/// distance infinite for a mesh without triangles.
struct ClosestPoint {
  Point3d point{0.0, 0.0, 0.0};
  uint32_t triangle = UINT32_MAX;
  double distance = 0.0;
};

class TriangleIndex {
 public:
  /// `mesh` must outlive the index. `cell`: the grid's cell size (two mean edges suit).
  TriangleIndex(const MeshView& mesh, double cell);
  /// The exact closest point of any triangle to p (a degenerate triangle counts by its
  /// vertices). `start_radius` is where the search starts; it widens until it finds one.
  ClosestPoint closest(Point3d p, double start_radius) const;
  /// The largest centroid-to-corner distance: a triangle whose closest point is at distance
  /// d has its centroid within d + max_reach.
  double max_reach() const { return max_reach_; }

 private:
  ClosestPoint search(Point3d p, double radius) const;

  const MeshView& mesh_;
  CpuGrid grid_;
  std::vector<Point4> centroids_;  // grid order, w unused
  double max_reach_ = 0.0;
};

}  // namespace fq
