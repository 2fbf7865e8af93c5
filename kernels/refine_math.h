// Per-vertex and per-face math of the refinement after the quadric filter ("qf+", see
// docs/ALGORITHM.md), written once for the CPU and the CUDA engine. It works on the mesh
// connectivity (vertex -> incident triangles) in normalized units (mean edge = 1):
//   1. relaxed_position: tangential relaxation restricted to the directions in which the
//      1-ring's normal tensor is weak, so folded triangles open up without any vertex
//      crossing a crease or a corner;
//   2. filtered_face_normal: one iteration of bilateral face-normal filtering (Zheng et
//      al. 2011) over the faces sharing a vertex;
//   3. updated_vertex: one iteration of Sun et al. 2007's vertex update, which moves each
//      vertex onto the planes of its filtered incident faces, plus a share of the move to
//      its 1-ring mean in the directions its filtered normals leave free (keeps triangles
//      from collapsing into slivers whose normals no longer follow the surface, without
//      rounding creases);
//   4. the clean-input guard: the mean change of the face normals between the input and the
//      result measures how rough the input was at the filter's scale; below `clean_below`
//      the input is kept, above `full_above` the result, linearly in between;
//   5. the rough-input path: above `rough_from` steps 2 and 3, with a wider normal filter
//      and in rounds, run again on the input itself (at that noise QF's grid neighbourhood
//      does more harm than good) and replace the result, fully from `rough_full` on
//      (kernels/refine_schedule.h).
// Every sum runs over a vertex's triangles in the CSR order (increasing triangle index), so
// results do not depend on the thread count.
#pragma once

#include <cmath>
#include <cstdint>

#include "kernels/gaussian.h"
#include "kernels/hd.h"
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
    t00 += s * n.x * n.x; t01 += s * n.x * n.y; t02 += s * n.x * n.z;
    t11 += s * n.y * n.y; t12 += s * n.y * n.z; t22 += s * n.z * n.z;
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

FQ_HD Vec3 eigenvector(const Sym3Eigen& e, int k) { return Vec3{e.vectors[0][k], e.vectors[1][k], e.vectors[2][k]}; }

}  // namespace detail

/// Interior manifold vertex: every 1-ring neighbour lies in exactly two incident triangles.
/// Boundary and non-manifold vertices are left where they are by the relaxation (a
/// 1-ring mean there pulls the boundary inward). Connectivity only: computed once per frame.
FQ_HD bool closed_fan(const FanView& m, uint32_t v) {
  const uint32_t b = m.vf_offsets[v], e = m.vf_offsets[v + 1];
  for (uint32_t k = b; k < e; ++k) {
    const uint32_t* tri = m.tris + 3 * size_t(m.vf_faces[k]);
    for (int c = 0; c < 3; ++c) {
      const uint32_t o = tri[c];
      if (o == v) continue;
      int count = 0;
      for (uint32_t k2 = b; k2 < e; ++k2) count += detail::has_vertex(m.tris + 3 * size_t(m.vf_faces[k2]), o) ? 1 : 0;
      if (count != 2) return false;
    }
  }
  return e > b;
}

/// Step 1. x_v + step * P (mean of the 1-ring − x_v), with P the projector on the
/// eigen-directions of T = Σ_f a_f n_f n_fᵀ (incident faces) whose eigenvalue is below
/// `feature_ratio` × the largest: the tangent plane on a smooth or flat region, the
/// crease line on a crease, nothing at a corner. A folded triangle still contributes
/// n nᵀ along the surface normal, so T keeps seeing the surface through the fold.
/// `closed` is closed_fan(m, v).
FQ_HD Vec3 relaxed_position(const FanView& m, const Vec3* x, uint32_t v, bool closed, float step,
                            float feature_ratio) {
  const Vec3 xv = x[v];
  if (!closed) return xv;
  OuterSum t;
  Vec3 ring{0.f, 0.f, 0.f};
  float count = 0.f;
  for (uint32_t k = m.vf_offsets[v]; k < m.vf_offsets[v + 1]; ++k) {
    const uint32_t* tri = m.tris + 3 * size_t(m.vf_faces[k]);
    const Vec3 a = x[tri[0]], b = x[tri[1]], c = x[tri[2]];
    const Vec3 n2 = cross(b - a, c - a);  // 2 a_f n_f
    const float len = std::sqrt(norm2(n2));
    if (len > 1e-12f) t.add(n2, 0.5f / len);  // a_f n nᵀ = n2 n2ᵀ / (2 |n2|)
    ring = ring + (a + b + c) - xv;  // the two other corners (each neighbour twice)
    count += 2.f;
  }
  const Sym3Eigen e = t.eigen();
  const float lmax = detail::largest(e);
  if (!(lmax > 0.f)) return xv;
  const Vec3 d = (1.0f / count) * ring - xv;
  Vec3 move{0.f, 0.f, 0.f};
FQ_UNROLL
  for (int k = 0; k < 3; ++k) {
    if (detail::free_weight(e.values[k], lmax, feature_ratio, feature_ratio) > 0.f) {
      const Vec3 ek = detail::eigenvector(e, k);
      move = move + dot(ek, d) * ek;
    }
  }
  return xv + step * move;
}

/// Step 2. Bilateral filtering of face normals (Zheng et al. 2011, eq. 3) over the faces
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
/// it starts to fade at θ = 42° and is gone from 76° on. Measured on the peer table (docs/QUALITY.md): a lower
/// end rounds fewer CAD edges (fandisk) but takes the share from curved scan regions
/// (max_planck), whose filtered normals spread too.
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

/// Step 3. One iteration of Sun et al. 2007 (eq. 8), the positions moved onto the planes
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

/// Step 4. Faces per partial sum of the mean normal change: fixed blocks, each summed in
/// the order below and then summed in block order, so the mean does not depend on the thread
/// count and both engines add in the same order.
constexpr uint32_t kNormalChangeBlock = 1024;

/// A block is added as one GPU warp adds it: lane l sums faces l, l + 32, l + 64, … of the
/// block in that order, then the lanes' sums are added pairwise 16, 8, 4, 2, 1 apart (a
/// shuffle tree). One thread walking a block's 1024 faces in a row took 1.5 ms on the dragon
/// (871K faces, an H100); a warp per block takes a few microseconds.
constexpr uint32_t kChangeLanes = 32;

/// Angle (radians) between face f's normal on the input (`in`, w ignored) and on the result;
/// 0 where either is degenerate.
FQ_HD float face_normal_change(const uint32_t* tris, const Point4* in, const Vec3* out, uint32_t f) {
  const uint32_t* t = tris + 3 * size_t(f);
  const Vec3 a0 = xyz(in[t[0]]), a = cross(xyz(in[t[1]]) - a0, xyz(in[t[2]]) - a0);
  const Vec3 b = cross(out[t[1]] - out[t[0]], out[t[2]] - out[t[0]]);
  if (!(norm2(a) > 0.f) || !(norm2(b) > 0.f)) return 0.f;
  return std::atan2(std::sqrt(norm2(cross(a, b))), dot(a, b));
}

/// Lane `lane`'s share of block `block`: face_normal_change over its faces below m, in order.
FQ_HD float normal_change_lane(const uint32_t* tris, uint32_t m, const Point4* in, const Vec3* out, uint32_t block,
                               uint32_t lane) {
  const uint32_t b = block * kNormalChangeBlock, e = b + kNormalChangeBlock < m ? b + kNormalChangeBlock : m;
  float sum = 0.f;
  for (uint32_t f = b + lane; f < e; f += kChangeLanes) sum += face_normal_change(tris, in, out, f);
  return sum;
}

/// Sum of face_normal_change over faces [block × kNormalChangeBlock, …) below m, the lanes
/// added as the warp's tree adds them (the CUDA engine's change_block_kernel).
inline float normal_change_block(const uint32_t* tris, uint32_t m, const Point4* in, const Vec3* out,
                                 uint32_t block) {
  float lanes[kChangeLanes];
  for (uint32_t l = 0; l < kChangeLanes; ++l) lanes[l] = normal_change_lane(tris, m, in, out, block, l);
  for (uint32_t apart = kChangeLanes / 2; apart > 0; apart /= 2)
    for (uint32_t l = 0; l < apart; ++l) lanes[l] = lanes[l] + lanes[l + apart];
  return lanes[0];
}

FQ_HD uint32_t normal_change_blocks(uint32_t m) { return (m + kNormalChangeBlock - 1) / kNormalChangeBlock; }

/// Mean of face_normal_change over the m faces, from the block sums, added in block order.
FQ_HD float mean_normal_change(const float* block_sums, uint32_t m) {
  float sum = 0.f;
  for (uint32_t k = 0; k < normal_change_blocks(m); ++k) sum += block_sums[k];
  return sum / float(m);
}

/// 0 at or below lo, 1 at or above hi, linear between.
FQ_HD float ramp(float r, float lo, float hi) {
  if (r >= hi) return 1.f;
  if (r <= lo) return 0.f;
  return (r - lo) / (hi - lo);
}

/// How much of the result to keep, from the block sums of normal_change_block: the mean
/// normal change r over the m faces, 0 for r <= clean_below, 1 for r >= full_above, linear
/// between. full_above <= 0 turns the guard off (1).
FQ_HD float refine_strength(const float* block_sums, uint32_t m, float clean_below, float full_above) {
  if (!(full_above > 0.f) || m == 0) return 1.f;
  return ramp(mean_normal_change(block_sums, m), clean_below, full_above);
}

/// Step 5. Share of the rough-input result in the output: 0 for r <= rough_from, 1 for
/// r >= rough_full, linear between; 0 when rough_full <= 0 (off).
FQ_HD float rough_weight(const float* block_sums, uint32_t m, float rough_from, float rough_full) {
  if (!(rough_full > 0.f) || m == 0) return 0.f;
  return ramp(mean_normal_change(block_sums, m), rough_from, rough_full);
}

/// The input moved `alpha` of the way to the result.
FQ_HD Vec3 guarded_position(Point4 in, Vec3 out, float alpha) { return xyz(in) + alpha * (out - xyz(in)); }

/// `a` moved `t` of the way to `b`.
FQ_HD Vec3 blended_position(Vec3 a, Vec3 b, float t) { return a + t * (b - a); }

}  // namespace fq
