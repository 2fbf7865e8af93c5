// The noise of a frame, estimated from the frame alone, written once for the CPU and the CUDA
// engine (docs/ALGORITHM.md, "Noise estimate").
//
// At a sample of vertices, a quadratic height field h(u, v) = b0 + b1 u + b2 v + b3 u² + b4 uv + b5 v²
// is fitted by least squares to the vertex's 2-ring (its neighbours and theirs, the vertex itself
// left out), in the frame of the vertex's area-weighted normal. The fit follows any smooth surface
// up to second order, so what is left of the vertex's own height, e = 0 − b0, is its noise along
// the normal plus the detail a quadratic over two rings cannot follow. With Gaussian noise of
// standard deviation σ along the normal, Var(e) = σ² (1 + λ), λ = [(XᵀX)⁻¹]₀₀ the leverage of the
// prediction, so z = e / √(1 + λ) has standard deviation σ whatever the ring's shape.
// Topological rings, not a ball in space: a ball also catches the other side of a thin part (a
// limb, a skirt), which a height field cannot fit.
//
// Noise and detail are told apart by how neighbours' residuals correlate. Detail (the bumps of
// a scanned surface, a capture's reconstruction relief) varies smoothly from a vertex to the
// next, so neighbours' residuals correlate positively; noise is independent from vertex to
// vertex, and each fit uses its neighbour's noise with a negative sign, so for pure noise the
// correlation is a known negative number w, computed exactly from the two fits' weights. With
// the measured correlation r and detail's own correlation d (kDetailCorrelation), the noise's
// share of the residual variance is (d − r) / (d − w), clamped to [0, 1].
// The frame's residual scale is robust: 1.4826 · median |z| over the samples (a crease or a
// corner, where the quadratic fails, changes a few of them, not the median); the correlation is
// measured on the pairs within 3.5 of that scale. σ̂ = scale · √share.
//
// Units are those of the engines' frame (mean edge = 1), so σ̂ is in mean edge lengths.
#pragma once

#include <cmath>
#include <cstdint>

#include "common/hd.h"
#include "kernels/refine_math.h"
#include "kernels/vec3.h"

namespace fq {

/// Vertices sampled per frame: every ⌈n / kNoiseSamples⌉-th vertex of the grid order (spread
/// over the whole surface). The median of 4096 samples is within about 2 % of the population's.
constexpr uint32_t kNoiseSamples = 4096;
/// Lag-one correlation of the residuals of a clean surface's detail: fitted with the filter's
/// constants (kernels/refine_plan.h); the clean meshes measured 0.06 (fandisk, with its creases
/// trimmed) to 0.28 (a capture frame), so 0.5 errs towards calling detail noise.
constexpr float kDetailCorrelation = 0.35f;
/// At most this many 2-ring neighbours enter a fit (a valence-6 mesh has 18).
constexpr int kMaxRing = 48;
/// Fewer neighbours than this leave too few degrees of freedom for six coefficients.
constexpr int kMinRing = 9;

FQ_HD uint32_t noise_sample_stride(uint32_t n) {
  return n > kNoiseSamples ? (n + kNoiseSamples - 1) / kNoiseSamples : 1;
}
FQ_HD uint32_t noise_sample_count(uint32_t n) { return n == 0 ? 0 : (n - 1) / noise_sample_stride(n) + 1; }

namespace detail {

FQ_HD int add_unique(uint32_t* ring, int count, uint32_t v) {
  for (int k = 0; k < count; ++k)
    if (ring[k] == v) return count;
  if (count < kMaxRing) ring[count++] = v;
  return count;
}

/// The vertices of v's incident triangles other than v, appended to ring (unique).
FQ_HD int add_one_ring(const FanView& m, uint32_t v, uint32_t self, uint32_t* ring, int count) {
  for (uint32_t k = m.vf_offsets[v]; k < m.vf_offsets[v + 1]; ++k) {
    const uint32_t* tri = m.tris + 3 * size_t(m.vf_faces[k]);
    for (int c = 0; c < 3; ++c)
      if (tri[c] != self) count = add_unique(ring, count, tri[c]);
  }
  return count;
}

/// Solves the symmetric positive definite 6×6 system a x = b in place (Cholesky); false when
/// a is not positive definite (a degenerate ring: collinear or coincident neighbours).
FQ_HD bool solve6(double (&a)[6][6], double (&b)[6]) {
  for (int j = 0; j < 6; ++j) {
    double d = a[j][j];
    for (int k = 0; k < j; ++k) d -= a[j][k] * a[j][k];
    if (!(d > 1e-12)) return false;
    a[j][j] = sqrt(d);
    for (int i = j + 1; i < 6; ++i) {
      double s = a[i][j];
      for (int k = 0; k < j; ++k) s -= a[i][k] * a[j][k];
      a[i][j] = s / a[j][j];
    }
  }
  for (int i = 0; i < 6; ++i) {
    double s = b[i];
    for (int k = 0; k < i; ++k) s -= a[i][k] * b[k];
    b[i] = s / a[i][i];
  }
  for (int i = 5; i >= 0; --i) {
    double s = b[i];
    for (int k = i + 1; k < 6; ++k) s -= a[k][i] * b[k];
    b[i] = s / a[i][i];
  }
  return true;
}

}  // namespace detail

/// A vertex's fit: its 2-ring, the weight of each ring vertex's height in the fitted height at
/// the vertex (the intercept row of (XᵀX)⁻¹Xᵀ, so that b0 = Σ a_k h_k), the leverage λ and the
/// standardized residual z.
struct RingFit {
  uint32_t ring[kMaxRing];
  float weight[kMaxRing];
  int count = 0;
  int first = 0;  ///< ring[0, first) is the 1-ring
  float z = 0.f;
  float leverage = 0.f;
  Vec3 normal{0.f, 0.f, 0.f};  ///< the fit frame's unit normal (set when ok)
  bool ok = false;
};

/// The frame a fit works in at vertex v (position p): its area-weighted unit normal n, a
/// tangent basis (t1, t2) and the inverse mean length of the `first` 1-ring edges, which makes
/// the in-plane coordinates order one (a well-scaled system). ok is false without a normal or
/// without edge length.
struct FitFrame {
  Vec3 p, n, t1, t2;
  double inv_edge = 0.0;
  bool ok = false;
};

FQ_HD FitFrame fit_frame(const FanView& m, const Vec3* x, uint32_t v, const uint32_t* ring, int first) {
  FitFrame f;
  f.p = x[v];
  Vec3 n{0.f, 0.f, 0.f};
  double edge = 0.0;
  for (uint32_t k = m.vf_offsets[v]; k < m.vf_offsets[v + 1]; ++k) {
    const uint32_t* tri = m.tris + 3 * size_t(m.vf_faces[k]);
    n = n + cross(x[tri[1]] - x[tri[0]], x[tri[2]] - x[tri[0]]);
  }
  for (int k = 0; k < first; ++k) edge += std::sqrt(double(norm2(x[ring[k]] - f.p)));
  const float len = std::sqrt(norm2(n));
  if (!(len > 0.f) || !(edge > 0.0)) return f;
  f.n = (1.0f / len) * n;
  // A tangent frame: the axis least aligned with n, crossed with n.
  const Vec3 axis = std::fabs(f.n.x) < 0.9f ? Vec3{1.f, 0.f, 0.f} : Vec3{0.f, 1.f, 0.f};
  const Vec3 t1 = cross(f.n, axis);
  f.t1 = (1.0f / std::sqrt(norm2(t1))) * t1;
  f.t2 = cross(f.n, f.t1);
  f.inv_edge = first / edge;
  f.ok = true;
  return f;
}

/// A ring vertex q in the frame: in-plane coordinates (u, w) and height h along the normal.
struct FitPoint {
  double u, w;
  float h;
};
FQ_HD FitPoint fit_point(const FitFrame& f, Vec3 q) {
  const Vec3 d = q - f.p;
  return {dot(d, f.t1) * f.inv_edge, dot(d, f.t2) * f.inv_edge, dot(d, f.n)};
}

/// The design row of the quadratic height field at (u, w).
FQ_HD void fit_row(const FitPoint& q, double (&row)[6]) {
  row[0] = 1.0;
  row[1] = q.u;
  row[2] = q.w;
  row[3] = q.u * q.u;
  row[4] = q.u * q.w;
  row[5] = q.w * q.w;
}

/// The point's weight in the fitted height at the vertex: its row times y = (XᵀX)⁻¹ e0.
FQ_HD double intercept_weight(const double (&y)[6], const FitPoint& q) {
  return y[0] + y[1] * q.u + y[2] * q.w + y[3] * q.u * q.u + y[4] * q.u * q.w + y[5] * q.w * q.w;
}

/// The fit's leverage and standardized residual from y[0] = λ and the fitted height b0.
FQ_HD void finish_fit(double y0, double b0, RingFit& fit) {
  fit.leverage = float(y0 > 0.0 ? y0 : 0.0);
  fit.z = float(-b0 / sqrt(1.0 + fit.leverage));
  fit.ok = true;
}

/// Fits vertex v (see the top of this file); fit.ok is false where v has fewer than kMinRing
/// 2-ring neighbours, no normal or a degenerate ring. The ring is the first kMaxRing distinct
/// vertices other than v met walking v's triangles' corners, then those of the triangles of
/// each 1-ring vertex in turn (kernels/cuda/noise_samples.cu builds the same list a warp at a
/// time).
FQ_HD void fit_ring(const FanView& m, const Vec3* x, uint32_t v, RingFit& fit) {
  fit.ok = false;
  int count = detail::add_one_ring(m, v, v, fit.ring, 0);
  const int first = count;
  for (int k = 0; k < first; ++k) count = detail::add_one_ring(m, fit.ring[k], v, fit.ring, count);
  fit.count = count;
  fit.first = first;
  if (count < kMinRing) return;
  const FitFrame frame = fit_frame(m, x, v, fit.ring, first);
  if (!frame.ok) return;
  fit.normal = frame.n;
  double a[6][6] = {}, y[6] = {1.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  for (int k = 0; k < count; ++k) {
    double row[6];
    fit_row(fit_point(frame, x[fit.ring[k]]), row);
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j <= i; ++j) a[i][j] += row[i] * row[j];
  }
  for (int i = 0; i < 6; ++i)
    for (int j = i + 1; j < 6; ++j) a[i][j] = a[j][i];
  if (!detail::solve6(a, y)) return;  // y = (XᵀX)⁻¹ e0
  double b0 = 0.0;
  for (int k = 0; k < count; ++k) {
    const FitPoint q = fit_point(frame, x[fit.ring[k]]);
    const double ak = intercept_weight(y, q);
    fit.weight[k] = float(ak);
    b0 += ak * q.h;
  }
  finish_fit(y[0], b0, fit);
}

/// The slide of a fitted vertex v (fit.ok): the tangential part of (mean of its 1-ring − x_v).
FQ_HD Vec3 ring_slide(const Vec3* x, uint32_t v, const RingFit& fit) {
  Vec3 sum{0.f, 0.f, 0.f};
  for (int k = 0; k < fit.first; ++k) sum = sum + x[fit.ring[k]];
  const Vec3 d = (1.0f / float(fit.first)) * sum - x[v];
  return d - dot(d, fit.normal) * fit.normal;
}

/// One sample of the estimate: the residuals of vertex v and of a neighbour (the first other
/// corner of v's first triangle), and the correlation their residuals would have if the
/// heights were white noise: with e_v = n_v − Σ a_vk n_k,
///   Cov(e_v, e_u) / σ² = −a_v(u) − a_u(v) + Σ_k a_v(k) a_u(k).
/// Surface detail that the quadratics cannot follow varies smoothly from one vertex to the
/// next, so the residuals of neighbours correlate positively; noise makes them correlate
/// negatively (each fit uses the other vertex's noise). NaN fields where a fit failed.
///
/// Also, for the directional part of the estimate (estimate_noise below): v's unit normal and
/// its slide, the part of the move from v to the mean of its 1-ring within v's tangent plane.
/// Noise that displaces vertices along one direction d (a range sensor's line of sight) moves
/// v by e·d: e·(n·d) along the normal, which z_v sees, and e·(d − (n·d) n) within the surface,
/// which the slide sees with the opposite sign. Shape and an irregular triangulation move the
/// slide and z_v independently of each other, so only such noise makes the two covary.
struct NoiseSample {
  float z_v, z_u, white_correlation;
  float height;  ///< v's residual before standardizing (e = z_v √(1 + λ)): its own noise counts once
  Vec3 normal, slide;
};

/// A sample with no usable fit.
FQ_HD NoiseSample no_noise_sample() {
  return NoiseSample{NAN, NAN, NAN, NAN, Vec3{0.f, 0.f, 0.f}, Vec3{0.f, 0.f, 0.f}};
}

/// The directional fields of the sample at v from its fit (fit.ok). A boundary vertex keeps none:
/// its 1-ring mean lies inside the surface, a slide of half an edge that no noise made.
FQ_HD void keep_direction_terms(const FanView& m, const Vec3* x, uint32_t v, const RingFit& fit,
                                NoiseSample& s) {
  if (!closed_fan(m, v)) return;
  s.height = fit.z * sqrtf(1.f + fit.leverage);
  s.normal = fit.normal;
  s.slide = ring_slide(x, v, fit);
}

/// The neighbour a sample at v pairs with: the first other corner of v's first triangle (v has one).
FQ_HD uint32_t sample_partner(const FanView& m, uint32_t v) {
  const uint32_t* tri = m.tris + 3 * size_t(m.vf_faces[m.vf_offsets[v]]);
  return tri[0] != v ? tri[0] : tri[1];
}

/// Cov(e_v, e_u) / σ² (c) as a correlation.
FQ_HD float white_correlation(double c, const RingFit& fv, const RingFit& fu) {
  return float(c / sqrt((1.0 + fv.leverage) * (1.0 + fu.leverage)));
}

FQ_HD NoiseSample noise_sample(const FanView& m, const Vec3* x, uint32_t v) {
  NoiseSample s = no_noise_sample();
  if (m.vf_offsets[v + 1] == m.vf_offsets[v]) return s;
  const uint32_t u = sample_partner(m, v);
  RingFit fv, fu;
  fit_ring(m, x, v, fv);
  if (!fv.ok) return s;
  s.z_v = fv.z;
  keep_direction_terms(m, x, v, fv, s);
  fit_ring(m, x, u, fu);
  if (!fu.ok) return s;
  s.z_u = fu.z;
  double c = 0.0;
  for (int k = 0; k < fv.count; ++k) {
    if (fv.ring[k] == u) c -= fv.weight[k];
    for (int l = 0; l < fu.count; ++l)
      if (fu.ring[l] == fv.ring[k]) c += double(fv.weight[k]) * fu.weight[l];
  }
  for (int l = 0; l < fu.count; ++l)
    if (fu.ring[l] == v) c -= fu.weight[l];
  s.white_correlation = white_correlation(c, fv, fu);
  return s;
}

/// The estimate from the samples (host only; both engines bring their samples to the host).
/// NaN fields of a sample are skipped; without a usable sample the estimate is 0.
///
/// The directional part: each sample's displacement as its fit and its slide show it, e_v n − slide
/// (e·d for noise e along d), gives the direction d they share most (the largest eigenvector of
/// their spread: a range scan's line of sight, along which its noise and its sampling both
/// displace vertices). For noise e·d along d, the slide holds −e·(1 − (n·d)²) along d and
/// z_v holds e·(n·d), so −E[(slide·d) sign(n·d) z_v] = σ_d² E[(1 − (n·d)²) |n·d|]: σ_d, the
/// noise along d, is read off that covariance. White noise, shape and an irregular mesh leave
/// it at zero up to its sampling error, and noise along the normals leaves a little of it where
/// the normals gather around one direction (a noisy normal scatters more than the surface's), so
/// only the part of the covariance beyond kDirectionalSignificance standard errors counts
/// (continuous in the samples: a covariance of twelve standard errors keeps three quarters).
struct NoiseEstimate {
  float residual = 0.f;           ///< 1.4826 × median |z_v|: noise and unfollowed detail together
  float correlation = 0.f;        ///< measured correlation of neighbours' residuals
  float white = 0.f;              ///< the correlation white noise would give
  float noise = 0.f;              ///< σ̂: the residual's white share
  float directional = 0.f;        ///< σ_d: noise along `direction`, mean edges (0: none found)
  Vec3 direction{0.f, 0.f, 0.f};  ///< unit d (zero without a usable sample)
  float alignment = 0.f;          ///< RMS of n·d over the samples: the share of σ_d along the normals
  /// An estimate of white noise σ alone (a noise given instead of estimated).
  static NoiseEstimate white_noise(float sigma) {
    NoiseEstimate e;
    e.noise = sigma;
    return e;
  }
};
/// Standard errors of the slide–residual covariance below which it is not read as directional noise:
/// capture frames with white or normal noise reach 2.6 (crane at 0.2), raw scans 12–13, depth noise 26.
constexpr double kDirectionalSignificance = 3.0;
NoiseEstimate estimate_noise(const NoiseSample* samples, uint32_t count);

}  // namespace fq
