// Error of a real scan against a reference surface it shares no vertices with: a raw range
// scan against the merged reconstruction of all the scans (../shared/meshes/scans), where the
// vertex-to-vertex measures of error_metrics.h do not apply.
//   normal error = mean angle between a scan face's normal and the normal of the reference
//                  triangle nearest the face's centroid (radians);
//   distance     = RMS distance of the faces' centroids to the reference surface, in a unit
//                  the caller gives (the raw scan's mean edge, so that filters compare);
//   normal error at the reference's scale = the same angle between each reference triangle's
//                  normal and the area-weighted normal of the scan faces nearest to it: a
//                  reconstruction is often coarser than its scans (the bunny's edges are 1.8 of
//                  a scan's), and a face-by-face angle then also counts the detail finer than
//                  the reference can hold; this one does not.
// Only faces over the reference count: a scan sees parts that the merge does not (the
// bottom of a statue, a hole the merge left open), and a face there would measure the hole,
// not the filter. The faces are chosen once, on the raw scan, and every filtered version is
// measured on the same faces.
#pragma once

#include <cstdint>
#include <vector>

#include "core/mesh_view.h"

namespace fq {

/// A face whose centroid is farther than this many scan mean edges from the reference is not
/// over it (a part the merge dropped or left out).
inline constexpr double kOverReferenceEdges = 3.0;

struct ScanError {
  double normal_error = 0.0;          ///< radians; NaN when no face counted
  double distance = 0.0;              ///< RMS centroid distance / unit; NaN when no face counted
  uint32_t faces_used = 0;            ///< faces counted (over the reference and not degenerate)
  double normal_error_coarse = 0.0;   ///< at the reference's scale (radians); NaN when none
  uint32_t reference_faces_used = 0;  ///< reference triangles nearest to at least 3 counted faces
  bool flipped = false;               ///< the scan is wound against the reference (angles taken as π − a)
};

/// 1 for each scan face over the reference: its centroid's closest reference point lies on a
/// triangle none of whose vertices is on the reference's boundary (an edge of one triangle),
/// within kOverReferenceEdges mean edges of the scan.
std::vector<uint8_t> faces_over_reference(const MeshView& reference, const MeshView& scan);

/// The error of the scan's triangles at `positions` (scan.num_vertices × 3 floats; scan's
/// own positions when null) over the faces marked in `counted` (all when null), distance in
/// units of `unit` (> 0). Scans are often wound the other way round from the reference:
/// when most counted faces point against their reference triangle, every angle is taken
/// against the flipped reference normal (π − a), and `flipped` says so (for both normal errors).
ScanError scan_error(const MeshView& reference, const MeshView& scan, const float* positions,
                     const uint8_t* counted, double unit);

}  // namespace fq
