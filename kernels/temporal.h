// A stream's memory for "qf+" across frames (docs/ALGORITHM.md, "Temporal filtering"): the last
// result of the stream, which the next frame's result is pulled towards where the surface held
// still (kernels/temporal_math.h). Vertex ids mean nothing from one capture frame to the next (a
// capture system may re-mesh every frame), so a frame finds its prior in space: each vertex
// looks up the nearest vertex of the last result, from a local estimate of the motion.
//
// The CPU engine runs this step on its result in input order; the CUDA engine runs the same
// per-vertex math (kernels/temporal_math.h) on the device (kernels/cuda/temporal_pass.cuh) and
// leaves the history in the same state, so a stream may move between engines.
#pragma once

#include <cstdint>
#include <vector>

#include "core/mesh_view.h"
#include "kernels/frame_matcher.h"
#include "kernels/refine_math.h"
#include "kernels/temporal_ids.h"
#include "kernels/temporal_math.h"
#include "kernels/vec3.h"

namespace fq {

struct TemporalHistory {
  std::vector<float> positions;  ///< the last result, 3 floats a vertex, input units
  std::vector<float> normals;    ///< its unit area-weighted vertex normals (see normals_pending)
  /// The motion the spatial track found for each vertex of `positions` to the history before it
  /// (3 floats a vertex, input units; empty when its frame found none: a first frame, a scene
  /// cut, a frame track A averaged). The next frame's motion estimate starts from it.
  std::vector<float> motion;
  /// After a frame track A averaged, `normals` are left empty until track B first reads them
  /// (settle_history_normals): while the ids hold, no frame does, and the normals cost a track-A
  /// frame a pass over its triangles (0.15–0.2 ms of a crane frame on an H200 host) for nothing.
  /// They come from the triangles track A keeps (ids.topology), whose fingerprint this is.
  uint64_t normals_pending = 0;
  double mean_edge = 0.0;  ///< the last result's frame's mean edge (input units)
  uint64_t frames = 0;     ///< frames filtered since the last reset (0: nothing kept)
  uint64_t resets = 0;     ///< scene cuts: frames that found no prior where they are
  /// Which write of a history this is: new (next_history_stamp) whenever a frame becomes the
  /// history, so an engine that keeps a device copy knows whether it is still this one.
  uint64_t stamp = 0;
  /// The host index over `positions` and the stamp it was built for; built by the CPU
  /// engine's step when it needs it (the CUDA engine matches on the device and leaves it).
  FrameMatcher index;
  uint64_t index_stamp = 0;
  /// Track A's memory (kernels/temporal_ids.h): the last averaged input, while the stream keeps
  /// its connectivity. A scene cut of the spatial track leaves it (clear()); forget() drops both.
  IdTrack ids;

  bool empty() const { return frames == 0; }
  /// Forgets the last result (a new stream, a restart, a scene cut); the reset count stays.
  void clear() {
    positions.clear();
    normals.clear();
    motion.clear();
    normals_pending = 0;
    frames = 0;
  }
  void forget() {
    clear();
    ids.clear();
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
  std::vector<uint32_t> vf_offsets, vf_faces, ring_corners;
  std::vector<Vec3> x, motion, offset, spare;
  std::vector<uint32_t> match;
  std::vector<float> detail, level, spare_level, share, normals;
  /// Track B's rounds of the motion estimate: each vertex's offset and rigid fit inputs.
  std::vector<MotionLanes> lanes, spare_lanes;
  /// Track A's (kernels/temporal_ids.cpp): quantities whose ring means run together, one to a lane.
  std::vector<Point4> packed, spare_packed;
  std::vector<Vec3> wide;  ///< track A's narrow motion estimate, then the wide one's difference
  /// Track A's rigid fit (kernels/rigid_motion.h): the last averaged positions, the ring means
  /// of RigidInputs' three lanes (and their spares) and the narrow estimate's correction.
  std::vector<Vec3> position, correction;
  std::vector<Point4> rigid[6];
};

/// The temporal step of one frame: `positions` (the frame's filtered result, input order, 3
/// floats a vertex) pulled along the normal towards `history` by `strength` ∈ [0, 1] at most,
/// where they agree once the motion is out; `mean_edge` (input units) and `noise` (the frame's
/// estimate, mean edges) set the scales. Then the result becomes the history of the next frame.
TemporalStep follow_history(const MeshView& mesh, std::vector<float>& positions, double mean_edge,
                            float noise, float strength, TemporalHistory& history, TemporalScratch& scratch,
                            int threads);

/// The end of every frame's temporal step, and all of it for a frame that track A averaged:
/// `positions` (the frame's result, input order, n vertices of `fan`) with its vertex normals
/// become the history the spatial track follows next, without a motion (the caller sets it).
void keep_as_history(const FanView& fan, uint32_t n, const std::vector<float>& positions, double mean_edge,
                     TemporalHistory& history, TemporalScratch& scratch, int threads);

/// The history's normals, where a frame track A averaged left them pending (normals_pending),
/// from the triangles of the connectivity track A keeps; a history whose connectivity track A
/// no longer holds (not a sequence the engines make) is cleared instead. Before track B reads it.
void settle_history_normals(TemporalHistory& history, TemporalScratch& scratch, int threads);

/// A stamp no history has had yet (never 0).
uint64_t next_history_stamp();

/// Area-weighted unit vertex normals (3 floats a vertex in `out`) of the n vertices `positions`
/// (3 floats a vertex): each vertex's sum over its fan (kernels/refine_math.h, vertex_normal),
/// as the CUDA engine computes them; in parallel, and the same sums in the same order as a
/// scatter over the triangles in index order. `faces` holds each triangle's cross product.
void vertex_normals(const FanView& fan, uint32_t n, const float* positions, std::vector<Vec3>& faces,
                    std::vector<float>& out, int threads);

}  // namespace fq
