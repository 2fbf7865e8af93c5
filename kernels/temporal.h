// A stream's memory for "qf+" across frames (docs/ALGORITHM.md, "Temporal filtering"): the last
// result of the stream, which the next frame's result is pulled towards where the surface held
// still (kernels/temporal_math.h). Vertex ids mean nothing from one capture frame to the next (a
// capture system may re-mesh every frame), so a frame finds its prior in space: each vertex
// looks up the nearest vertex of the last result, from a local estimate of the motion.
//
// Both engines run this step on the host, on their result in input order: one copy of the code.
#pragma once

#include <cstdint>
#include <vector>

#include "core/mesh_view.h"
#include "kernels/nearest_vertex.h"
#include "kernels/vec3.h"

namespace fq {

struct TemporalHistory {
  std::vector<float> positions;  ///< the last result, 3 floats a vertex, input units
  std::vector<float> normals;    ///< its unit area-weighted vertex normals
  NearestVertexIndex index;      ///< over `positions`, cells of one mean edge
  uint64_t frames = 0;           ///< frames filtered since the last reset (0: nothing kept)
  uint64_t resets = 0;           ///< scene cuts: frames that found no prior where they are

  bool empty() const { return frames == 0; }
  /// Forgets the last result (a new stream, a restart, a scene cut); the reset count stays.
  void clear() {
    positions.clear();
    normals.clear();
    frames = 0;
  }
};

/// What one frame's temporal step did.
struct TemporalStep {
  float coverage = 0.f;  ///< share of vertices with a prior vertex within reach (0: no history)
  float share = 0.f;     ///< mean pull towards the prior (strength × agreement) over all vertices
  bool reset = false;    ///< a scene cut: under kMinPriorCoverage found a prior, the history restarts
};

/// Buffers of the step, kept between frames.
struct TemporalScratch {
  std::vector<uint32_t> vf_offsets, vf_faces;
  std::vector<Vec3> x, motion, offset, spare;
  std::vector<uint32_t> match;
  std::vector<float> detail, level, spare_level, normals;
};

/// The temporal step of one frame: `positions` (the frame's filtered result, input order, 3
/// floats a vertex) pulled along the normal towards `history` by `strength` ∈ [0, 1] at most,
/// where they agree once the motion is out; `mean_edge` (input units) and `noise` (the frame's
/// estimate, mean edges) set the scales. Then the result becomes the history of the next frame.
TemporalStep follow_history(const MeshView& mesh, std::vector<float>& positions, double mean_edge, float noise,
                            float strength, TemporalHistory& history, TemporalScratch& scratch, int threads);

/// Area-weighted unit vertex normals of `xyz` (3 floats a vertex) over the mesh's triangles.
void vertex_normals(const MeshView& mesh, const float* xyz, std::vector<float>& out, int threads);

}  // namespace fq
