// The passes of one "qf+" frame, every strength a continuous function of the noise σ the frame is
// filtered for (its estimate × strength, or the noise given; mean edge lengths). Host only: both
// engines make the plan once per frame and run the same passes (kernels/refine_math.h).
//
// Why these functions (docs/ALGORITHM.md, "qf+: a filter that follows the noise"):
// - Face normals of a frame with noise σ scatter by about 2σ radians (a corner moving σ along
//   the normal tilts its triangle by σ over the triangle's height). The normal filter's range
//   grows with σ; σ → 0 makes it 0: a clean frame's normals are their own filtered normals, and
//   the vertex update then has nothing to move.
// - More noise needs more averaging: normal passes grow linearly with σ, the vertex passes that
//   realize the filtered normals too, and at heavy noise whole rounds (filter the normals of
//   the updated surface again) are added, quadratically in σ.
// - Counts are real numbers: the last pass of each kind counts only its fraction, so the result
//   moves continuously with σ instead of jumping where a count would round.
// - Tangential moves: isotropic noise displaces a vertex by 2σ² (squared, mean) within the
//   tangent plane. The vertex update also slides vertices towards regular triangles; where the
//   slide is larger than the noise explains (an irregular capture triangulation), it is cut back
//   (refine_math.h, limited_position), so vertices do not drift along the surface (textures
//   would swim).
// The constants were fitted once on fandisk, bunny, crane frame 0 and armadillo (seed 1, noise
// 0.05–0.5) against the best of Open3D's smoothers, and checked on the meshes, seeds and noise
// levels of the quality matrix they were not fitted on (docs/QUALITY.md).
#pragma once

#include <cmath>

#include "core/params.h"
#include "kernels/gaussian.h"
#include "kernels/noise_estimate.h"
#include "kernels/vec3.h"

namespace fq {

/// `count` passes of which the last counts only `last` (in (0, 1]) of its change.
struct Passes {
  int count;
  float last;
};

/// x ≥ 0 passes: ⌈x⌉ of them, the last one counting x − ⌈x⌉ + 1.
inline Passes passes_of(float x) {
  if (!(x > 0.f)) return {0, 1.f};
  const int count = static_cast<int>(std::ceil(x));
  return {count, x - float(count - 1)};
}

struct RefinePlan {
  float noise;                 ///< σ the strengths come from, in mean edge lengths
  Passes rounds;               ///< normal filtering then vertex updates, this many times over
  Passes normal_passes;        ///< per round
  Passes vertex_passes;        ///< per round
  Gaussian gs, gr;             ///< the normal filter's spatial and range kernels
  float tangential_step;       ///< share of the move to the 1-ring mean per vertex update
  float tangential_allowance;  ///< squared tangential move kept per unit of turn (kSlidePerTurn σ²)
  /// The frame's directional noise (noise_estimate.h): its variance σ_d² (× strength²), the
  /// squared tangential move it explains where its direction lies in the tangent plane, and its
  /// unit direction (zero: none found, or a noise given).
  float directional_allowance;
  Vec3 noise_direction;
};

constexpr float kRoundsPerNoise2 = 16.f;    ///< rounds = 1 + 16σ²
constexpr float kNormalPassesAtZero = 1.f;  ///< normal passes = 1 + 10σ
constexpr float kNormalPassesPerNoise = 10.f;
constexpr float kVertexPassesAtZero = 2.f;  ///< vertex passes = 2 + 15σ
constexpr float kVertexPassesPerNoise = 15.f;
constexpr float kRangeScale = 1.f;  ///< range σ_r = σ^0.3 (chord length |n_i − n_j|)
constexpr float kRangeExponent = 0.3f;
constexpr float kNormalSigmaS = 0.7f;  ///< spatial extent of the normal filter, mean edges
constexpr float kTangentialStep = 0.1f;
/// The share fades in linearly up to this noise: a clean frame has no triangles for it to
/// repair, and at a corner whose fan is uneven it would move the vertex off the surface.
constexpr float kShareFullFrom = 0.05f;
/// The squared slide a vertex keeps, per σ² and per unit of its local turn (face_turn in
/// refine_math.h): a slide stays where the noise distorted the triangles (the filter turned them)
/// and is cut where it would only move detail or an irregular triangulation along the surface.
/// Light white noise turns triangles a little (σ = 0.05 on crane and armadillo: 0.2–0.3 σ² kept
/// at the median face, where the noise's own tangential share is 2σ² and sliding it back is
/// invisible in the normals but costs vertex error); heavy noise turns them more (σ = 0.2: 4σ²,
/// σ = 0.5: 20σ²) and grazing depth noise flips some (14σ² at the 90th percentile of bunny at
/// depth 0.2). 100 was chosen from sweeps of 10–100 (docs/ALGORITHM.md); before, the allowance
/// was a fixed 3σ² whatever the triangles.
constexpr float kSlidePerTurn = 100.f;
constexpr float kMinRange = 1e-4f;  ///< the range at σ = 0 (a Gaussian needs σ > 0)

/// The normal noise the strengths follow when it is estimated: σ̂, or the directional noise's
/// part along the normals (σ_d × the RMS of n·d) where that is larger (noise along one direction
/// scatters the vertices within the surface too, which disturbs the fits σ̂ is read from).
inline float normal_noise(const NoiseEstimate& e) { return std::fmax(e.noise, e.directional * e.alignment); }

/// The directional noise's RMS part within the tangent planes, σ_d √(1 − RMS(n·d)²): what it
/// slides vertices by. Noise along the normals of a frame seen head-on is directional noise
/// along its normal, with no part within the surface.
inline float tangential_noise(const NoiseEstimate& e) {
  return e.directional * std::sqrt(std::fmax(0.f, 1.f - e.alignment * e.alignment));
}

/// The plan for a frame whose estimated noise is `estimate` (its noise ignored when the
/// parameters give the noise). Directional noise also lets the vertex update slide further: its
/// tangential share grows by the share of the noise that lies within the surface, q = σ_t² /
/// (σ_t² + σ_n²) (σ_t = tangential_noise), up to twice the share at q → 1, and the slide
/// allowance holds the directional noise's tangential variance at each vertex.
inline RefinePlan plan_refinement(const RefineParams& r, const NoiseEstimate& estimate) {
  // A noise given is white noise of that σ: no directional part.
  const NoiseEstimate e = r.known_noise > 0.f ? NoiseEstimate::white_noise(r.known_noise) : estimate;
  const float sn = normal_noise(e), sd = e.directional, st = tangential_noise(e);
  const float s = r.strength * sn;
  const float range = s > 0.f ? kRangeScale * std::pow(s, kRangeExponent) : 0.f;
  const float directional_share = st > 0.f ? st * st / (st * st + sn * sn) : 0.f;
  RefinePlan p;
  p.noise = s;
  p.rounds = passes_of(1.f + kRoundsPerNoise2 * s * s);
  p.normal_passes = passes_of(kNormalPassesAtZero + kNormalPassesPerNoise * s);
  p.vertex_passes = passes_of(kVertexPassesAtZero + kVertexPassesPerNoise * s);
  p.gs = Gaussian::with_sigma(kNormalSigmaS);
  // A clean frame (σ = 0) weights only normals within 1e-4 of the face's own: nothing moves.
  p.gr = Gaussian::with_sigma(std::fmax(range, kMinRange));
  p.tangential_step = kTangentialStep * (1.f + directional_share) * std::fmin(1.f, s / kShareFullFrom);
  p.tangential_allowance = kSlidePerTurn * s * s;
  p.directional_allowance = r.strength * r.strength * sd * sd;
  p.noise_direction = sd > 0.f ? e.direction : Vec3{0.f, 0.f, 0.f};
  return p;
}

/// The plan for white noise of `estimate` (mean edges) alone.
inline RefinePlan plan_refinement(const RefineParams& r, float estimate) {
  return plan_refinement(r, NoiseEstimate::white_noise(estimate));
}

}  // namespace fq
