// Per-vertex math of temporal filtering ("qf+" with a stream history, kernels/temporal.h),
// written once for the CPU and the CUDA engine, in the frame's normalized units (mean edges).
//
// A frame's filtered surface is pulled along the normal towards the stream's last result
// where the two agree once the motion between them is taken out:
//  0. prediction: where the last result holds the motion its own frame found, each vertex
//     starts from that of its nearest prior vertex, averaged over kPredictionPasses rings (a
//     stream's motion changes little from one frame to the next); else from rest;
//  1. motion: each vertex's offset to the prior vertex nearest to x + m, averaged over
//     kMotionPasses rings, with the rigid motion that best fits those offsets over the same
//     rings (kernels/rigid_motion.h), is the local motion m: a local ICP, whose rounds close
//     in on the prior surface along it and not only across it (the frame's own error and the
//     prior's average out over the rings); kMotionIterations rounds, then the last lookup at x + m;
//  2. detail: o = n·(p − x − m), with p, n the matched prior vertex and its normal, is what is
//     left once the motion is out: the two frames' independent errors, along the normal;
//  3. agreement: where the local mean of o² is within the frame's noise the match is right and
//     x moves by strength·o along n; where it is far larger the match is wrong (a limb moved
//     past another, a tangential motion the rings cannot see) and the frame stays alone.
// Tangential positions are left to the frame: a surface prior says nothing about where along
// the surface a vertex sits (docs/ALGORITHM.md, "Temporal filtering", says what was tried).
#pragma once

#include <cmath>
#include <cstdint>

#include "common/hd.h"
#include "kernels/rigid_motion.h"
#include "kernels/vec3.h"

namespace fq {

/// A prior vertex farther than this (mean edges of the new frame, after the motion estimate)
/// is another part of the surface.
constexpr float kPriorReach = 3.f;
/// Under this share of vertices with a prior within reach, the frame is a scene cut: the
/// history is dropped and the frame filtered alone.
constexpr float kMinPriorCoverage = 0.5f;
/// Ring means of the last frame's motion that make the prediction (four rings: about 60
/// vertices on a regular mesh).
constexpr int kPredictionPasses = 4;
/// Ring means of the offsets and of the rigid fit's inputs in each round of the motion
/// estimate. A translation over a footprint this wide would miss a limb's rotation; the rigid
/// fit follows it, and the wider footprint leaves less of the two surfaces' errors in the
/// motion and holds more curvature, which is what settles a motion along the surface. With the
/// rigid fit, eight rings took crane's surface flicker (shuffled frames 0-59, five rounds)
/// 2.3 % below four; sixteen, 0.5 % lower still for twice the passes.
constexpr int kMotionPasses = 8;
/// Rounds of lookup and motion estimate before the final lookup from x + m. A lookup from x
/// finds the prior vertex nearest to where the point is, which trails where it came from by
/// up to the motion; each round from x + m closes part of that, and each rigid fit to nearest
/// points (point-to-point ICP) closes a part of the motion along the surface. On crane shuffled
/// (frames 0-59) two rounds with the rigid fit left MFNE 0.1717 and surface flicker 0.0970, five
/// 0.1695 and 0.0943, eight 0.1688 and 0.0933 for 60 % more lookups: five.
constexpr int kMotionIterations = 5;
/// Ring means of o² that make the agreement's local level.
constexpr int kAgreementPasses = 2;
/// The agreement's scale, in units of the frame's estimated noise: exp(-1/2) where the local
/// RMS of o is this many noise sigmas.
constexpr float kPriorTolerance = 0.5f;

/// How far the detail o of a vertex whose local mean of o² is `level` may be trusted.
FQ_HD float prior_agreement(float level, float tolerance) {
  return tolerance > 0.f ? std::exp(-level / (2.f * tolerance * tolerance)) : 0.f;
}

/// The pull of a vertex towards its prior: strength × the agreement of its local level of o².
FQ_HD float prior_share(float level, float strength, float noise) {
  return strength * prior_agreement(level, kPriorTolerance * noise);
}

/// The share of a frame's n vertices that found a prior vertex (`covered` of them).
FQ_HD float prior_coverage(uint64_t covered, uint32_t n) {
  return n > 0 ? float(double(covered) / double(n)) : 0.f;
}

/// Whether a frame whose prior coverage is `coverage` is a scene cut (the history restarts).
FQ_HD bool scene_cut(float coverage) { return coverage < kMinPriorCoverage; }

/// The motion a vertex's estimate starts from: its nearest prior vertex's own motion
/// (`prior`, input units; TemporalHistory::motion) in the frame's mean edges (`unit` = 1 / the
/// frame's mean edge), none where it found no prior vertex.
FQ_HD Vec3 predicted_motion(bool found, Vec3 prior, float unit) {
  return found ? unit * prior : Vec3{0.f, 0.f, 0.f};
}

/// What one round's ring means carry at a vertex x (mean edges, from the frame's origin) whose
/// nearest prior vertex lies at x + offset: the rigid fit's inputs and the offset, averaged
/// together in one pass (64 bytes a vertex).
struct MotionLanes {
  RigidInputs fit;
  Point4 offset;  ///< xyz: the offset; w unused
};

FQ_HD MotionLanes operator+(const MotionLanes& a, const MotionLanes& b) {
  return {{a.fit.p + b.fit.p, a.fit.q0 + b.fit.q0, a.fit.q1 + b.fit.q1}, a.offset + b.offset};
}
FQ_HD MotionLanes operator*(float s, const MotionLanes& a) {
  return {{s * a.fit.p, s * a.fit.q0, s * a.fit.q1}, s * a.offset};
}

/// A vertex's lanes from its position x and its offset to its prior vertex (none: zero).
FQ_HD MotionLanes motion_lanes(Vec3 x, Vec3 offset) {
  return {rigid_inputs(x, offset), Point4{offset.x, offset.y, offset.z, 0.f}};
}

/// The motion of a vertex at x from its lanes' ring means: the mean offset, with the rigid
/// correction of the fit over the same rings (zero where the neighbourhood has no rank two).
FQ_HD Vec3 fitted_motion(const MotionLanes& mean, Vec3 x) {
  const Vec3 m = xyz(mean.offset);
  return m + rigid_correction(mean.fit, m, x);
}

/// The detail left between x (moved by the motion estimate m) and its prior vertex p with
/// unit normal n: signed, along n.
FQ_HD float prior_detail(Vec3 x, Vec3 m, Vec3 p, Vec3 n) { return dot(n, p - (x + m)); }

// Track A (kernels/temporal_ids.h): the frame's input averaged with the last averaged input
// through the vertex ids, once the ids are shown to follow a smooth motion.

/// Ring means of the id displacement that make its smooth part, the motion (four rings: about
/// 60 vertices, so the two frames' noise leaves an eighth of itself in the motion). A ring mean
/// reproduces a motion affine along the surface; a rotation of a curved part it leaves short by
/// the rotation of its shrinkage, which the rigid fit of each neighbourhood puts back
/// (kernels/rigid_motion.h).
constexpr int kIdMotionPasses = 4;
/// Ring means past kIdMotionPasses that make the motion's wide estimate: where the id
/// displacement is as smooth over eight rings as noise allows (wide_share), the wide estimate
/// is the motion, and the noise the narrow one would leave in it, smooth over a few rings and
/// so what a viewer sees as the surface breathing, is averaged out too.
constexpr int kIdWidePasses = 4;
/// Ring means of the squared non-smooth displacement that make a vertex's local level.
constexpr int kIdAgreementPasses = 2;
/// A vertex's level may be this many times the frame's typical level (its median) before the
/// last averaged input loses weight there: local levels of pure noise spread about ±20 % over
/// two rings, so twice the median is a misfit, not chance.
constexpr float kIdTolerance = 2.f;
/// Above this typical RMS of the non-smooth displacement (mean edges) the ids are not the same
/// surface points from frame to frame (noise of 0.2 mean edges gives about 0.4): track B.
constexpr float kIdReach = 2.f;

/// The weight of the last averaged input at a vertex whose local level of non-smooth
/// displacement is `level`, in a frame whose typical level is `typical`: the full `strength`
/// within kIdTolerance of the typical level, then falling as 1 / level (the misfit the prior
/// would bring grows as its level, so its weight shrinks in proportion).
FQ_HD float id_share(float level, float typical, float strength) {
  const float allowed = kIdTolerance * typical;
  return level > allowed ? strength * (allowed / level) : strength;
}

/// The share of a vertex's non-smooth displacement that is noise, from how much of it survives a
/// ring mean: noise is white from vertex to vertex, so a ring mean keeps `white` (its weights'
/// sum of squares) of its variance, while a motion the smooth part missed (a swinging limb at
/// high speed) is smooth over a ring and survives whole. With noise σ² and a missed motion e²,
/// the ring mean keeps q = (white σ² + e²) / (σ² + e²) of the local level, so
/// σ² / (σ² + e²) = (1 − q) / (1 − white): the weight the last input deserves by the misfit it
/// would bring (the rule of id_share). `coherent` and `level` are the local means of the squared
/// ring mean of the non-smooth displacement and of its square.
FQ_HD float noise_part(float coherent, float level, float white) {
  if (!(level > 0.f) || !(white < 1.f)) return 1.f;
  const float r = (1.f - coherent / level) / (1.f - white);
  return r < 0.f ? 0.f : (r > 1.f ? 1.f : r);
}

/// Past this many frames a track's count stops (history_weight is the strength long before).
constexpr uint32_t kIdFramesCounted = 1u << 20;
/// The most a vertex takes of the last averaged input when it holds `frames` frames: the stream's
/// `strength`, or less while the track is young. A still surface seen k times with independent
/// noise is best estimated by the mean of the k views, in which the last averaged input (the
/// mean of k − 1) weighs (k − 1) / k; the recursive average reaches its own weight after
/// 1 / (1 − strength) frames, and until then that mean is the better one (at strength 0.75 the
/// second frame's average keeps 0.63 of the noise's variance with weight 0.75, 0.5 with 1/2).
FQ_HD float history_weight(float strength, uint32_t frames) {
  const float running = frames > 0 ? float(frames) / float(frames + 1) : 0.f;
  return running < strength ? running : strength;
}

/// The share g of the wide motion estimate's difference δ from the narrow one that a vertex
/// takes into its motion m + g δ. δ is the two footprints' noise (variance E, `expected`) plus
/// b, what the wide estimate misses where the motion bends within eight rings (a limb, a fast
/// non-rigid motion; the narrow one follows it), and the narrow estimate's noise is the wide
/// one's minus δ's, so the motion's squared error is the narrow one's − 2 g E + g² (E + b²): least at
/// g = E / (E + b²). With b² read as what the local level of δ² (`level`) holds beyond E, that
/// is min(1, E / level): the whole wide estimate where δ looks like noise, less as it bends.
FQ_HD float wide_share(float level, float expected) { return level > expected ? expected / level : 1.f; }

/// The narrow rest r of a vertex's id displacement packed with its square, for the agreement's
/// ring means (one quantity a lane).
FQ_HD Point4 rest_packed(Vec3 r) { return Point4{r.x, r.y, r.z, dot(r, r)}; }

/// The second pass's inputs at a vertex from the first pass's ring mean m of rest_packed: the
/// level's running mean of r², the coherence test's square of the rest's ring mean, and the
/// square of the wide estimate's difference w.
FQ_HD Point4 level_inputs(Point4 m, Vec3 w) {
  const Vec3 c = xyz(m);
  return Point4{m.w, dot(c, c), dot(w, w), 0.f};
}

/// A vertex's weight of the last averaged input and its share of the wide estimate.
struct IdWeights {
  float share;
  float wide;
};

/// The last step's per-vertex rule, with the frame's values: the history's weight
/// (history_weight), the typical level, IdTopology::wide_white and the mean edge (input units).
struct IdBlend {
  float weight, typical, wide_white, edge;

  /// From m, the ring mean of the second pass's (coherence square, wide square), the vertex's
  /// local `level` and its white-noise share `white`.
  FQ_HD IdWeights weights(Point4 m, float level, float white) const {
    const float noise = noise_part(m.x, level, white);
    return {id_share(level, typical, weight) * noise, wide_share(m.y, wide_white * noise * level)};
  }
  /// What the vertex moves back by (input units): its share of what is left of the displacement
  /// once the motion (narrow estimate + the wide share of the difference `wide`) is out;
  /// `offset` is the narrow rest.
  FQ_HD Vec3 back(IdWeights w, Vec3 offset, Vec3 wide) const {
    const Vec3 rest = offset - w.wide * wide;
    return (w.share * edge) * rest;
  }
};

/// Whether a frame whose typical level of non-smooth id displacement is `typical` (squared mean
/// edges) has ids that follow the surface.
FQ_HD bool ids_follow(float typical) { return typical <= kIdReach * kIdReach; }

}  // namespace fq
