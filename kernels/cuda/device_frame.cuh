// Device state of the CUDA engine for one frame, kept between frames: every array is
// grow-only, so a steady stream of same-sized frames allocates nothing. Per-vertex
// arrays are in grid (cell) order, as in the CPU engine's CpuFrame.
#pragma once

#include <cstdint>

#include "kernels/cuda/device_buffer.cuh"
#include "kernels/cuda/device_grid.cuh"
#include "kernels/cuda/packed_quadric.cuh"
#include "kernels/quadric.h"
#include "kernels/triangle_math.h"
#include "kernels/vec3.h"

namespace fq::cuda {

struct DeviceFrame {
  uint32_t n = 0;  ///< vertices
  uint32_t m = 0;  ///< triangles

  // Pinned staging: normalized points and triangles up, positions and labels down.
  PinnedBuffer<Point4> h_points;
  PinnedBuffer<uint32_t> h_tris;
  PinnedBuffer<Vec3> h_moved;
  PinnedBuffer<uint32_t> h_labels;  ///< n labels, then the cluster count
  PinnedBuffer<int> h_bounds;

  DeviceBuffer<Point4> in_points;  ///< input order, normalized, w = 0
  DeviceBuffer<uint32_t> in_tris;  ///< input vertex indices
  DeviceGrid grid;
  DeviceBuffer<Point4> points;  ///< sorted; w = barycentric area after base_quadrics
  DeviceBuffer<uint32_t> tris;  ///< sorted vertex indices
  DeviceBuffer<TriangleGeom> tri_geom;
  DeviceBuffer<float4> accum;  ///< 4 per vertex: quadric sums, area, normal (atomic variant)
  DeviceBuffer<uint32_t> vf_count, vf_start, vf_slot, vf_faces;  ///< vertex -> triangles (gather variant)
  DeviceBuffer<Quadric> base, nbhd, bl;
  DeviceBuffer<PackedQuadric> base_p, nbhd_p, bl_p;  ///< the same, for the team kernels' loads
  DeviceBuffer<Vec3> vnormal, moved;
  DeviceBuffer<Vec3> moved_in_order;

  // Bilateral baseline: triangles in centroid-grid order.
  DeviceBuffer<Point4> tri_in;  ///< centroid, w = area; triangle order
  DeviceGrid tri_grid;
  DeviceBuffer<Point4> tri_points;
  DeviceBuffer<Vec3> tri_normals, tri_mollified;
  DeviceBuffer<int> bounds;  ///< order-preserving ints of lo.xyz, hi.xyz

  // Clustering.
  DeviceBuffer<float> score;
  DeviceBuffer<uint32_t> next, root;
  DeviceBuffer<uint32_t> root_flag, root_scan;  ///< n + 1, input order
  DeviceBuffer<uint32_t> labels;                ///< n labels, then the cluster count
  DeviceBuffer<unsigned char> temp;             ///< CUB scratch
  DeviceBuffer<uint32_t> link_parent;           ///< link forest before the cut, input order
  DeviceBuffer<float> link_p;
  PinnedBuffer<uint32_t> h_link_parent;
  PinnedBuffer<float> h_link_p;
};

}  // namespace fq::cuda
