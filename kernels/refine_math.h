// Per-vertex and per-face math of "qf+" (see docs/ALGORITHM.md), written once for the CPU and the
// CUDA engine. It works on the mesh connectivity (vertex -> incident triangles) in normalized
// units (mean edge = 1), in rounds planned by kernels/refine_plan.h:
//   1. filtered_face_normal: one pass of bilateral face-normal filtering (Zheng et al. 2011)
//      over the faces sharing a vertex;
//   2. updated_vertex: one pass of Sun et al. 2007's vertex update, which moves each vertex
//      onto the planes of its filtered incident faces, plus a share of the move to its 1-ring
//      mean in the directions its filtered normals leave free (keeps triangles from collapsing
//      into slivers whose normals no longer follow the surface, without rounding creases);
//   3. limited_position: after the rounds, the part of each vertex's move within its tangent
//      plane is kept only as far as the noise turned the vertex's triangles (face_turn,
//      refine_plan.h).
// Fractional passes (partial_normal, partial_position) make the result continuous in the plan.
// Every sum runs over a vertex's triangles in the CSR order (increasing triangle index), so
// results do not depend on the thread count.
#pragma once

#include <cmath>
#include <cstdint>

#include "common/hd.h"
#include "kernels/gaussian.h"
#include "kernels/sym3_eigen.h"
#include "kernels/triangle_math.h"
#include "kernels/vec3.h"

namespace fq {

/// Connectivity: triangles (3 indices each) and the vertex -> triangles CSR.
struct FanView {
  const uint32_t* tris;
  const uint32_t* vf_offsets;  ///< n + 1
  const uint32_t* vf_faces;
};

/// A sum Σ s n nᵀ (upper triangle): a normal tensor, or a projector on eigen-directions.
struct OuterSum {
  float t00 = 0.f, t01 = 0.f, t02 = 0.f, t11 = 0.f, t12 = 0.f, t22 = 0.f;
  FQ_HD void add(Vec3 n, float s) {
    t00 += s * n.x * n.x;
    t01 += s * n.x * n.y;
    t02 += s * n.x * n.z;
    t11 += s * n.y * n.y;
    t12 += s * n.y * n.z;
    t22 += s * n.z * n.z;
  }
  FQ_HD Sym3Eigen eigen() const { return sym3_eigen(t00, t01, t02, t11, t12, t22); }
  FQ_HD Vec3 apply(Vec3 d) const {
    return Vec3{t00 * d.x + t01 * d.y + t02 * d.z, t01 * d.x + t11 * d.y + t12 * d.z,
                t02 * d.x + t12 * d.y + t22 * d.z};
  }
};

namespace detail {

FQ_HD bool has_vertex(const uint32_t* tri, uint32_t v) { return tri[0] == v || tri[1] == v || tri[2] == v; }

FQ_HD float largest(const Sym3Eigen& e) {
  const float l01 = e.values[0] > e.values[1] ? e.values[0] : e.values[1];
  return l01 > e.values[2] ? l01 : e.values[2];
}

/// How free a normal tensor leaves the direction of its eigenvalue l (lmax the largest, > 0):
/// 1 below lo × lmax, 0 from hi × lmax on, linear between (lo = hi: a hard cut).
FQ_HD float free_weight(float l, float lmax, float lo, float hi) {
  return l < lo * lmax ? 1.f : l >= hi * lmax ? 0.f : (hi * lmax - l) / ((hi - lo) * lmax);
}

FQ_HD Vec3 eigenvector(const Sym3Eigen& e, int k) {
  return Vec3{e.vectors[0][k], e.vectors[1][k], e.vectors[2][k]};
}

}  // namespace detail

/// Interior manifold vertex: every 1-ring neighbour lies in exactly two incident triangles.
/// Boundary and non-manifold vertices get no tangential share in the vertex update (a 1-ring
/// mean there pulls the boundary inward). Connectivity only: computed once per frame.
FQ_HD bool closed_fan(const FanView& m, uint32_t v) {
  const uint32_t b = m.vf_offsets[v], e = m.vf_offsets[v + 1];
  for (uint32_t k = b; k < e; ++k) {
    const uint32_t* tri = m.tris + 3 * size_t(m.vf_faces[k]);
    for (int c = 0; c < 3; ++c) {
      const uint32_t o = tri[c];
      if (o == v) continue;
      int count = 0;
      for (uint32_t k2 = b; k2 < e; ++k2)
        count += detail::has_vertex(m.tris + 3 * size_t(m.vf_faces[k2]), o) ? 1 : 0;
      if (count != 2) return false;
    }
  }
  return e > b;
}

/// Step 1. Bilateral filtering of face normals (Zheng et al. 2011, eq. 3) over the faces
/// that share a vertex with f (f included), each counted once:
///   n_f' = normalize(Σ_j a_j G_σs(|c_f − c_j|) G_σr(|n_f − n_j|) n_j).
/// `geom` gives centroids and areas (fixed during the iterations), `normals` the current
/// iterate. A face whose sum vanishes keeps its normal.
FQ_HD Vec3 filtered_face_normal(const FanView& m, const TriangleGeom* geom, const Vec3* normals, uint32_t f,
                                Gaussian gs, Gaussian gr) {
  const uint32_t* tri = m.tris + 3 * size_t(f);
  const Vec3 nf = normals[f], cf = geom[f].centroid;
  Vec3 acc{0.f, 0.f, 0.f};
  for (int c = 0; c < 3; ++c) {
    const uint32_t v = tri[c];
    for (uint32_t k = m.vf_offsets[v]; k < m.vf_offsets[v + 1]; ++k) {
      const uint32_t j = m.vf_faces[k];
      const uint32_t* tj = m.tris + 3 * size_t(j);
      // Counted at the first corner of f it shares.
      if (c >= 1 && detail::has_vertex(tj, tri[0])) continue;
      if (c >= 2 && detail::has_vertex(tj, tri[1])) continue;
      // G_s G_r as one exp of the summed exponents (half the exps of the hot loop).
      const float w = geom[j].area * std::exp(norm2(cf - geom[j].centroid) * gs.neg_inv_two_sigma2 +
                                              norm2(nf - normals[j]) * gr.neg_inv_two_sigma2);
      acc = acc + w * normals[j];
    }
  }
  const Vec3 n = normalized_or_zero(acc);
  return norm2(n) > 0.f ? n : nf;
}

/// Eigenvalue ratios λ_k / λ_max of the filtered normals' tensor Σ_f n_f n_fᵀ (v's faces) over
/// which the vertex update's tangential share fades out along e_k. A crease whose two sides'
/// normals differ by θ, its faces split evenly, gives λ_2 / λ_max = tan²(θ/2): the share across
/// it starts to fade at θ = 42° and is gone from 76° on. Measured on the peer table (docs/QUALITY.md): a
/// lower end rounds fewer CAD edges (fandisk) but takes the share from curved scan regions (max_planck),
/// whose filtered normals spread too.
constexpr float kCrossingFadeFrom = 0.15f;
constexpr float kCrossingGoneAt = 0.6f;

/// The directions in which the vertex update's tangential share may move v: the projector
/// Σ_k w_k e_k e_kᵀ (upper triangle) over the eigenvectors of its filtered normals' tensor
/// T = Σ_f n_f n_fᵀ, w_k = detail::free_weight between kCrossingFadeFrom and kCrossingGoneAt:
/// the tangent plane on a smooth region, the crease line on a crease, nothing at a corner,
/// never the normal. Moving across a crease toward the 1-ring mean would round it. Zero on
/// an open fan (boundary, non-manifold). The normals are fixed over a round's vertex
/// updates, so it is computed once per round.
using FreeDirections = OuterSum;

/// FreeDirections of v from the filtered normals. `closed` is closed_fan(m, v).
FQ_HD FreeDirections free_directions(const FanView& m, const Vec3* normals, uint32_t v, bool closed) {
  FreeDirections p;
  if (!closed) return p;
  OuterSum t;
  for (uint32_t k = m.vf_offsets[v]; k < m.vf_offsets[v + 1]; ++k) t.add(normals[m.vf_faces[k]], 1.f);
  const Sym3Eigen e = t.eigen();
  const float lmax = detail::largest(e);
  if (!(lmax > 0.f)) return p;
  FQ_UNROLL
  for (int k = 0; k < 3; ++k) {
    const float w = detail::free_weight(e.values[k], lmax, kCrossingFadeFrom, kCrossingGoneAt);
    p.add(detail::eigenvector(e, k), w);
  }
  return p;
}

/// Step 2. One iteration of Sun et al. 2007 (eq. 8), the positions moved onto the planes
/// of the filtered normals: x_v + 1/|F_v| Σ_{f∋v} n_f (n_f · (c_f − x_v)), c_f the current
/// centroid, faces with a zero normal (degenerate) skipped; plus `tangential_step` × the move
/// from x_v to its 1-ring mean within `dirs` (free_directions of v), read from the same
/// iterate in the same walk over v's triangles.
FQ_HD Vec3 updated_vertex(const FanView& m, const Vec3* x, const Vec3* normals, uint32_t v,
                          const FreeDirections& dirs, float tangential_step) {
  const Vec3 xv = x[v];
  Vec3 acc{0.f, 0.f, 0.f}, ring{0.f, 0.f, 0.f};
  float planes = 0.f, count = 0.f;
  for (uint32_t k = m.vf_offsets[v]; k < m.vf_offsets[v + 1]; ++k) {
    const uint32_t f = m.vf_faces[k];
    const uint32_t* tri = m.tris + 3 * size_t(f);
    const Vec3 sum = x[tri[0]] + x[tri[1]] + x[tri[2]];
    ring = ring + sum - xv;
    count += 2.f;
    const Vec3 n = normals[f];
    if (!(norm2(n) > 0.f)) continue;
    acc = acc + dot(n, (1.0f / 3.0f) * sum - xv) * n;
    planes += 1.f;
  }
  const Vec3 p = planes > 0.f ? xv + (1.0f / planes) * acc : xv;
  if (!(tangential_step > 0.f)) return p;
  if (!(count > 0.f)) return p;
  return p + tangential_step * dirs.apply((1.0f / count) * ring - xv);
}

/// Sun et al.'s update alone (updated_vertex without the tangential share).
FQ_HD Vec3 normal_driven_position(const FanView& m, const Vec3* x, const Vec3* normals, uint32_t v) {
  return updated_vertex(m, x, normals, v, FreeDirections{}, 0.f);
}

/// A fractional pass: `prev` turned `w` (in (0, 1]) of the way to `next`, renormalized.
FQ_HD Vec3 partial_normal(Vec3 prev, Vec3 next, float w) {
  if (!(w < 1.f)) return next;
  const Vec3 n = normalized_or_zero(prev + w * (next - prev));
  return norm2(n) > 0.f ? n : next;
}

/// A fractional pass or round: `prev` moved `w` of the way to `next`.
FQ_HD Vec3 partial_position(Vec3 prev, Vec3 next, float w) {
  return w < 1.f ? prev + w * (next - prev) : next;
}

/// Unit area-weighted normal of vertex v on positions x (zero where it has no area).
FQ_HD Vec3 vertex_normal(const FanView& m, const Vec3* x, uint32_t v) {
  Vec3 acc{0.f, 0.f, 0.f};
  for (uint32_t k = m.vf_offsets[v]; k < m.vf_offsets[v + 1]; ++k) {
    const uint32_t* tri = m.tris + 3 * size_t(m.vf_faces[k]);
    acc = acc + cross(x[tri[1]] - x[tri[0]], x[tri[2]] - x[tri[0]]);
  }
  return normalized_or_zero(acc);
}

/// Step 3, first part. The part of the move from `in` to `out` that lies in the tangent plane
/// of the unit normal n (the result's vertex normal).
FQ_HD Vec3 tangential_move(Vec3 in, Vec3 out, Vec3 n) {
  const Vec3 d = out - in;
  return d - dot(n, d) * n;
}

/// Mean of e over v and the other corners of its triangles (each neighbour counted once per
/// triangle it shares with v): the local level of a per-vertex quantity.
template <class T>
FQ_HD T ring_mean(const FanView& m, const T* e, uint32_t v) {
  T sum = e[v];
  float count = 1.f;
  for (uint32_t k = m.vf_offsets[v]; k < m.vf_offsets[v + 1]; ++k) {
    const uint32_t* tri = m.tris + 3 * size_t(m.vf_faces[k]);
    for (int c = 0; c < 3; ++c) {
      if (tri[c] == v) continue;
      sum = sum + e[tri[c]];
      count += 1.f;
    }
  }
  return (1.f / count) * sum;
}

/// Step 3's per-vertex quantities, made local levels together by the same ring_mean passes.
struct SlideLevel {
  float energy;  ///< |t|², the squared tangential move
  float turn;    ///< how far the filter turned the vertex's triangles (face_turn)
  float across;  ///< 1 − (n·d)²: the share of a displacement along the noise's direction d that lies
                 ///< in the tangent plane (0 without a direction)
};
FQ_HD SlideLevel operator+(SlideLevel a, SlideLevel b) {
  return {a.energy + b.energy, a.turn + b.turn, a.across + b.across};
}
FQ_HD SlideLevel operator*(float s, SlideLevel a) { return {s * a.energy, s * a.turn, s * a.across}; }

/// Step 3, second part. Mean over v's triangles of (1 − n_in·n_out)/2: 0 where the filter left
/// every triangle's orientation alone, ≈ θ²/4 for triangles turned by θ, 1 for a triangle the
/// noise had flipped. A triangle with no normal (collapsed) counts 1/2. Noise that moves a vertex
/// within the surface only turns triangles as far as it distorts them; this measures that harm.
FQ_HD float face_turn(const FanView& m, const Point4* in, const Vec3* out, uint32_t v) {
  float sum = 0.f;
  float count = 0.f;
  for (uint32_t k = m.vf_offsets[v]; k < m.vf_offsets[v + 1]; ++k) {
    const uint32_t* tri = m.tris + 3 * size_t(m.vf_faces[k]);
    const Vec3 a = xyz(in[tri[0]]), b = xyz(in[tri[1]]), c = xyz(in[tri[2]]);
    const Vec3 before = normalized_or_zero(cross(b - a, c - a));
    const Vec3 after = normalized_or_zero(cross(out[tri[1]] - out[tri[0]], out[tri[2]] - out[tri[0]]));
    sum += fmaxf(0.f, 0.5f * (1.f - dot(before, after)));  // a dot rounded above 1 is no turn
    count += 1.f;
  }
  return count > 0.f ? sum / count : 0.f;
}

/// ring_mean passes that make a vertex's tangential energy and turn local levels (two rings).
constexpr int kEnergyPasses = 2;

/// Step 3's quantities of vertex v before their ring means: its tangential move t (normal n of
/// the result) and `direction`, the unit direction of the frame's directional noise or zero.
FQ_HD SlideLevel slide_level(const FanView& m, const Point4* in, const Vec3* out, uint32_t v, Vec3 t, Vec3 n,
                             Vec3 direction) {
  const float nd = dot(n, direction);
  return {norm2(t), face_turn(m, in, out, v), fmaxf(0.f, norm2(direction) - nd * nd)};
}

/// The squared slide the noise explains at a vertex of local `level`: `per_turn` (refine_plan.h,
/// kSlidePerTurn σ²) per unit of turn, plus the directional noise's own tangential variance,
/// σ_d² (`directional`) times the share of its direction within the tangent plane.
FQ_HD float slide_allowance(const SlideLevel& level, float per_turn, float directional) {
  return per_turn * level.turn + directional * level.across;
}

/// Step 3. The result `out` of vertex v with its tangential move `t` scaled by g = min(1,
/// allowance / energy): `energy` is the local mean of |t|² (ring_mean, twice), `allowance` the
/// part the noise explains (slide_allowance). Where the vertices slid no more than that, the slide undoes
/// noise and stays; where they slid more (an irregular triangulation pulled towards regular triangles, or
/// detail the filter hardly turned), only that share of it stays (the Wiener gain of the slide: signal over
/// signal plus noise).
FQ_HD Vec3 limited_position(Vec3 out, Vec3 t, float energy, float allowance) {
  allowance = fmaxf(allowance, 0.f);  // below 0 (rounding) the division would give -inf * 0
  const float g = energy > allowance ? allowance / energy : 1.f;
  return out - (1.f - g) * t;
}

}  // namespace fq
