// The closest point of a triangle mesh to a query point, exactly, through a grid of the
// triangles' centroids: eval/surface_distance.cpp (vertex to surface) and eval/scan_error.cpp
// (a scan's faces against a reconstruction) search the same way. The same grid answers where
// a line through a point first meets the mesh (eval/surface_flicker.cpp samples a result
// surface along the clean normals).
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

/// Where a line p + s·dir meets a triangle: the point, s, and the point's barycentric
/// weights on the triangle's corners. triangle is UINT32_MAX when the line meets none.
struct LineHit {
  Point3d point{0.0, 0.0, 0.0};
  uint32_t triangle = UINT32_MAX;
  double s = 0.0;
  double weights[3] = {0.0, 0.0, 0.0};
};

class TriangleIndex {
 public:
  /// `mesh` must outlive the index. `cell`: the grid's cell size (two mean edges suit).
  TriangleIndex(const MeshView& mesh, double cell);
  /// The exact closest point of any triangle to p (a degenerate triangle counts by its
  /// vertices). `start_radius` is where the search starts; it widens until it finds one.
  ClosestPoint closest(Point3d p, double start_radius) const;
  /// The intersection with the smallest |s| of the line p + s·dir (dir of unit length, both
  /// directions) with the triangles, for |s| <= max_s; ties go to the lower triangle index.
  /// A line in a triangle's plane does not meet it (no single point to report).
  LineHit nearest_line_hit(Point3d p, Point3d dir, double max_s) const;
  /// The barycentric weights of point q (on or near the plane of `triangle`) on its corners;
  /// a degenerate triangle gives all the weight to its first corner.
  void barycentric(uint32_t triangle, Point3d q, double weights[3]) const;
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
