// Temporal filtering when a stream keeps its connectivity ("track A", docs/ALGORITHM.md,
// "Temporal filtering"): many capture pipelines track a template, or run keyframes whose frames
// share faces and vertex count, so vertex i of one frame is vertex i of the next. Then the
// frame's INPUT is averaged with the stream's last averaged input before the frame is
// filtered, which takes the noise out of what a viewer sees far better than pulling the
// filtered surface towards the last one (kernels/temporal.h, "track B", which needs no ids).
//
// The ids are not trusted blindly: the displacement d = x_t - a_{t-1} between the raw frame and
// the last averaged input is split into its smooth part (ring means: the motion, over four
// rings and, as far as the noise says the motion is that smooth, over eight, each with the
// rotation its neighbourhood's rigid fit adds, kernels/rigid_motion.h) and the rest
// (the two frames' noise, and wherever an id does not follow the surface). A vertex takes
// strength x the share of the rest that its local level allows; where the rest is far above
// the frame's typical level (an id that slid, a tracking error) the frame stays alone; where
// it is so large across the frame that ids cannot be the same points, the frame falls back to
// track B.
#pragma once

#include <cstdint>
#include <vector>

#include "core/mesh_view.h"
#include "kernels/vec3.h"

namespace fq {

struct TemporalScratch;
struct TemporalHistory;

/// What the step reads that depends on the connectivity alone, built on the first frame of a
/// connectivity that the step averages and kept while the fingerprint holds: the vertex ->
/// triangles table (the result's normals), the ring table in blocks (kernels/vertex_ring.h,
/// BlockRing), the white-noise share of the coherence test, smoothed as the test smooths it, and
/// that of the wide motion estimate; and the triangles, for the history's normals.
/// About 118 bytes a vertex on a closed triangle mesh, crane's (two triangles a vertex: 4 + 24
/// for the fans and 24 for the triangles; 4 × the widest ring of a block of four, some 14, and
/// 4 + 1 for the rings; 4 for the white share), beside the 12 of `averaged`; IdTrack::bytes()
/// counts them.
struct IdTopology {
  uint64_t fingerprint = 0;  ///< the connectivity it was built for, with its counts (0, 0: none)
  uint32_t vertices = 0, triangles = 0;
  std::vector<uint32_t> vf_offsets, vf_faces, ring_rows, ring_slots;
  /// The connectivity's triangles (3 indices each): the history's normals from them when
  /// they are first read (settle_history_normals).
  std::vector<uint32_t> triangles_kept;
  std::vector<float> ring_inv_count;
  std::vector<float> white;  ///< per vertex, after kIdAgreementPasses ring means
  /// What white noise leaves in the wide motion estimate's difference from the narrow one, per
  /// unit of what it leaves in the narrow rest (the medians of their local levels, measured
  /// on white_probe): the noise the difference should show where the motion is smooth.
  float wide_white = 0.f;

  bool holds(uint64_t f, uint32_t n, uint32_t m) const {
    return !white.empty() && fingerprint == f && vertices == n && triangles == m;
  }
  void clear() {
    fingerprint = 0;
    vertices = triangles = 0;
    white.clear();
  }
};

/// A stream's memory for track A: its last averaged input and the connectivity it had.
struct IdTrack {
  std::vector<float> averaged;  ///< a_{t-1}: 3 floats a vertex, input order and units
  uint64_t connectivity = 0;    ///< connectivity_fingerprint of the frame it came from
  uint32_t vertices = 0;        ///< that frame's vertex count
  uint32_t frames = 0;          ///< frames averaged into it since the track restarted (history_weight)
  /// Which write of `averaged` this is (next_history_stamp, kernels/temporal.h), new whenever it
  /// changes: an engine that keeps a copy on its device knows the copy by it. 0: none.
  uint64_t stamp = 0;
  IdTopology topology;  ///< keyed by its own fingerprint: a refused frame leaves it valid

  bool empty() const { return averaged.empty(); }
  void clear() {
    averaged.clear();
    connectivity = 0;
    vertices = 0;
    frames = 0;
    stamp = 0;
    topology.clear();
  }
  /// Bytes the track holds (its buffers' capacities), for the memory it costs a stream.
  size_t bytes() const;
};

/// A hash of a frame's vertex count and triangles: equal for frames that share connectivity
/// (and almost never for two that do not). Parallel over chunks of triangles, each hashed in
/// four independent lanes, and the same value for any thread count.
uint64_t connectivity_fingerprint(const MeshView& mesh, int threads);

/// connectivity_fingerprint(mesh) for the frame of a stream with `track`: the fingerprint of
/// the track's tables when it holds them for the frame's counts and triangles (compared as they
/// are, an exact test at memory speed: 14-26 µs on crane's 20K triangles where hashing them took
/// 40-57, an H200 host's CPU, `fqbench --track-ids`), else the hash. The tables are built for
/// the fingerprint that begin_id_step is given, which every caller computes from the frame's
/// own triangles.
uint64_t frame_connectivity(const MeshView& mesh, const IdTrack& track, int threads);

/// What one frame's track-A step did.
struct IdStep {
  bool ran = false;      ///< the averaged input replaced the frame's (else: track B or alone)
  bool refused = false;  ///< same connectivity, but the ids did not follow a smooth motion
  float share = 0.f;     ///< mean weight of the last averaged input over all vertices
  float residual = 0.f;  ///< typical RMS of the non-smooth part of the id displacement (mean edges)
  float wide = 0.f;      ///< mean share of the wide motion estimate over all vertices (wide_share)
};

/// The track-A step of a frame: when `track` holds an averaged input of the same connectivity
/// (`fingerprint`), writes the frame's averaged input into `averaged` (3 floats a vertex) and
/// returns ran = true; `track` then holds it for the next frame. Otherwise (a first frame, a
/// new connectivity, refused ids) `track` restarts from the raw frame and ran is false.
/// `mean_edge` (input units) sets the scale; `strength` ∈ [0, 1] is the stream's temporal
/// strength: the most a vertex takes of the last averaged input.
IdStep average_with_ids(const MeshView& mesh, uint64_t fingerprint, double mean_edge, float strength,
                        IdTrack& track, std::vector<float>& averaged, TemporalScratch& scratch, int threads);

// The step in three parts, for an engine that runs its per-vertex math on a device
// (kernels/cuda/id_pass.cuh): average_with_ids is begin_id_step, the math, finish_id_step.

/// The host part before the math: false where the step cannot run (a first frame, a new
/// connectivity, a frame without a scale: `track` restarts from the raw frame); else true, with
/// the connectivity's tables in track.topology (built on its first frame there, once).
bool begin_id_step(const MeshView& mesh, uint64_t fingerprint, double mean_edge, IdTrack& track,
                   TemporalScratch& scratch, int threads);

/// What the math found, for finish_id_step.
struct IdMath {
  float typical = 0.f;     ///< the median of the vertices' local levels (squared mean edges)
  double share_sum = 0.0;  ///< Σ of the vertices' weights of the last averaged input
  double wide_sum = 0.0;   ///< Σ of their shares of the wide motion estimate
};

/// The host part after the math: ids that do not follow (ids_follow(typical)) restart `track`
/// from the raw frame and the step is refused; else the track counts the frame (its averaged
/// input, written by the math, gets a new stamp) and the step ran.
IdStep finish_id_step(const MeshView& mesh, uint64_t fingerprint, const IdMath& math, IdTrack& track);

/// The most a vertex takes of `track`'s last averaged input this frame (history_weight).
float id_history_weight(const IdTrack& track, float strength);

/// A probe of white noise at vertex v: three components of ±1 (unit variance), from v's bits
/// alone, so the share of white noise the motion's two footprints keep (IdTopology::wide_white)
/// is measured the same way on every machine and for any thread count.
Vec3 white_probe(uint32_t v);

/// The origin of the rigid fit's positions (kernels/rigid_motion.h): the middle of the frame's
/// bounding box (input units; min and max do not depend on the order they are taken in, so both
/// engines find the same), so that products of positions stay as small as floats need: a
/// neighbourhood's covariance is some ten square mean edges, taken as a difference of ring means
/// of products up to the frame's half extent squared. By that arithmetic crane (up to 87 mean
/// edges across) keeps some four of a float's seven digits of the covariance; a frame a
/// thousand mean edges across keeps two or three: a rotation error of about 0.01 rad, some
/// 0.005 mean edges of motion at a vertex.
Vec3 id_origin(const MeshView& mesh, int threads);

/// After a frame that track A averaged: its result (`positions`, input order) becomes the
/// history the spatial track follows should the connectivity change, its normals pending
/// (TemporalHistory::normals_pending) on the connectivity the track keeps (call it only after a
/// step that ran).
void keep_averaged_result(const MeshView& mesh, const std::vector<float>& positions, double mean_edge,
                          TemporalHistory& history);

}  // namespace fq
