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

/// Reductions of the raw frame (frame_checks.cu), read back in one piece.
struct FrameStats {
  int lo[3], hi[3];                              ///< coordinate bounds, as ordered ints
  unsigned long long bad_coordinate, bad_index;  ///< first faults, or kNone
  double edge_sum;                               ///< over the three edges of every triangle
};

struct DeviceFrame {
  uint32_t n = 0;  ///< vertices
  uint32_t m = 0;  ///< triangles

  // Pinned staging: the raw frame up, positions and labels down.
  PinnedBuffer<unsigned char> h_upload;  ///< coordinates, then indices, as the caller gave them
  PinnedBuffer<FrameStats> h_stats;
  PinnedBuffer<unsigned char> h_download;  ///< positions: 3 floats per vertex, input order and units
  PinnedBuffer<uint32_t> h_labels;         ///< n labels, then the cluster count
  PinnedBuffer<int> h_bounds;

  DeviceBuffer<float> in_coords;   ///< 3 per vertex, input units and order
  DeviceBuffer<uint32_t> in_tris;  ///< input vertex indices
  DeviceBuffer<FrameStats> stats;
  DeviceBuffer<double> edge_partials;
  DeviceBuffer<Point4> in_points;  ///< input order, normalized, w = 0
  DeviceGrid grid;
  DeviceBuffer<Point4> points;  ///< sorted; w = barycentric area after base_quadrics
  DeviceBuffer<uint32_t> tris;  ///< sorted vertex indices
  DeviceBuffer<TriangleGeom> tri_geom;
  DeviceBuffer<uint32_t> vf_count, vf_start, vf_slot, vf_faces;  ///< vertex -> triangles
  DeviceBuffer<Quadric> base, nbhd, bl;
  DeviceBuffer<PackedQuadric> base_p, nbhd_p, bl_p;  ///< the same, for the team kernels' loads
  DeviceBuffer<Vec3> vnormal, moved;
  DeviceBuffer<float> out_coords;  ///< moved, 3 per vertex, input order and units

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
