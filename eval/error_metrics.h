// Geometric error between a candidate and a reference mesh with the same vertices and
// connectivity (a filtered or noisy copy): the two numbers reported by the paper's
// denoising comparisons and by fqfilter.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "common/status.h"
#include "core/mesh_view.h"

namespace fq {

/// Ok when `candidate` has the same vertex and triangle counts as `reference` and the same
/// triangle indices; otherwise a message that names the first difference. Callers holding
/// two meshes check this before calling the metrics below, which take raw positions.
Status check_same_connectivity(const MeshView& reference, const MeshView& candidate);

/// Length of the diagonal of the mesh's bounding box: the scale every error measure here is
/// divided by. NaN without vertices.
double bbox_diagonal(const MeshView& mesh);

/// Vertex RMSE normalized by the reference's bounding-box diagonal:
///   sqrt( (1/V) * sum_i |x_i - x_ref_i|^2 ) / |bbox_max(ref) - bbox_min(ref)|.
/// Dividing by the diagonal makes numbers comparable across meshes of any scale (a value
/// of 1e-3 is 0.1% of the object's size).
/// Precondition: `positions` holds 3 * reference.num_vertices floats in reference order.
/// Returns NaN when the reference has no vertices or a zero diagonal (no scale to
/// normalize by).
double rmse_over_diagonal(const MeshView& reference, const float* positions);

/// Mean face normal error.
struct MfneResult {
  double mean_radians = 0.0;  ///< mean over the faces used; NaN when none was used
  uint32_t faces_used = 0;
  uint32_t faces_skipped = 0;  ///< degenerate (no normal) in the reference or the candidate
};

/// Mean over triangles of the angle, in radians in [0, pi], between the reference face
/// normal and the candidate face normal (same triangle indices, `positions` as the
/// candidate's vertices). A triangle whose normal is undefined in either mesh (zero or
/// near-zero area relative to its edge lengths) is skipped and counted, not averaged in.
/// Precondition: as for rmse_over_diagonal, and reference indices are in range.
MfneResult mean_face_normal_error(const MeshView& reference, const float* positions);

/// Triangle `tri`'s normal times twice its area (the cross product of its edges from the
/// first corner), in doubles: what the measures here, the scan error and the noise build on.
std::array<double, 3> face_area_normal(const float* positions, const uint32_t* tri);

/// Area-weighted vertex normals, unnormalized (the sum of the incident triangles'
/// face_area_normal; zero where a vertex has none): callers divide by the length where they
/// use one, as the normal noise always did, so that its noisy meshes stay bit for bit what
/// they were.
std::vector<double> area_vertex_normals(const MeshView& mesh);

/// The angle, in radians in [0, pi], between the normal of triangle `ta` of positions `pa`
/// and that of triangle `tb` of positions `pb`; NaN when either is degenerate (the rule of
/// mean_face_normal_error). The meshes may differ (a scan against its reconstruction).
double face_normal_angle(const float* pa, const uint32_t* ta, const float* pb, const uint32_t* tb);

}  // namespace fq
