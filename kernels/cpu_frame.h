// Scratch state of the CPU engine for one frame, kept between frames so that a steady
// stream of same-sized frames reuses its allocations. All per-vertex arrays are in grid
// (cell) order: neighbours of a vertex sit close in memory.
#pragma once

#include <cstdint>
#include <vector>

#include "kernels/frame_prep.h"
#include "kernels/grid_build.h"
#include "kernels/noise_estimate.h"
#include "kernels/quadric.h"
#include "kernels/refine_math.h"
#include "kernels/triangle_math.h"
#include "kernels/vec3.h"

namespace fq {

struct CpuFrame {
  Normalization norm;
  std::vector<Vec3> normalized;  ///< input order
  CpuGrid grid;                  ///< grid.order: sorted -> input index
  std::vector<uint32_t> rank;    ///< input -> sorted index
  std::vector<Point4> points;    ///< sorted positions, w = barycentric area
  std::vector<uint32_t> tris;    ///< triangles with sorted indices
  std::vector<TriangleGeom> tri_geom;
  std::vector<uint32_t> vf_offsets;  ///< vertex -> incident triangles (CSR, sorted ids)
  std::vector<uint32_t> vf_faces;
  std::vector<Quadric> base, nbhd, bl;
  std::vector<Vec3> vnormal, moved;
  // "qf+": the noise samples, double buffers of positions and face normals.
  std::vector<NoiseSample> noise_samples;
  std::vector<Vec3> refine_x;
  std::vector<uint8_t> refine_closed;  ///< closed_fan per vertex
  std::vector<TriangleGeom> refine_geom;
  std::vector<Vec3> refine_n[2];
  std::vector<FreeDirections> refine_free;  ///< per vertex, per round of the vertex update
  std::vector<Vec3> refine_round;           ///< the positions before a fractional last round
  std::vector<Vec3> refine_t;               ///< per vertex: its tangential move (limited_position)
  std::vector<SlideLevel> refine_e[2];  ///< per vertex: squared tangential move and turn, then local means
  // Bilateral baseline: triangles in centroid-grid order.
  CpuGrid tri_grid;
  std::vector<Point4> tri_points;  ///< centroid, w = area
  std::vector<Vec3> tri_normals, tri_mollified;
  // Clustering.
  std::vector<float> score;
  std::vector<uint32_t> next;
};

}  // namespace fq
