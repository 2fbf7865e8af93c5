// Temporal measures of a filtered sequence read off the result's *surface*, never its vertex
// ids or triangles, so they hold for a re-meshed result stream. Each clean vertex c (clean
// unit area-weighted normal n_c) samples the result along the line c + s·n_c: the crossing
// nearest c within 3 clean mean edges ℓ, else the closest point of the result. Its height
// h = s / ℓ and the result's smooth-shaded normal n_r there (the barycentric mix of the
// result's unit vertex normals) give, weighted by the clean vertices' areas:
//   height RMS            RMS of h, per frame;
//   smooth-normal error   mean angle(n_r, n_c), per frame;
//   surface flicker (SF)  RMS of h_t − h_t−1, per pair of frames;
//   shading flicker (ShF) RMS of |(n_r,t − n_r,t−1) − (n_c,t − n_c,t−1)|, per pair of frames.
// The pair measures need clean frames that share their vertices (a tracked reference).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "core/mesh_view.h"

namespace fq {

/// How far along the clean normal the sampler looks for a crossing, in clean mean edges.
inline constexpr double kSampleReach = 3.0;

/// The result surface seen from each vertex of one clean frame.
struct SurfaceSample {
  double mean_edge = 0.0;             ///< ℓ: the clean frame's mean edge
  std::vector<double> height;         ///< h per clean vertex (clean mean edges, along n_c)
  std::vector<double> result_normal;  ///< n_r, 3 a vertex (unit; zero where the result has none)
  std::vector<double> clean_normal;   ///< n_c, 3 a vertex (unit; zero where the clean mesh has none)
  std::vector<double> area;           ///< a third of the incident clean triangles' areas
  std::vector<uint8_t> hit;           ///< 1: the line met the result within kSampleReach; 0: closest point
  uint32_t vertices() const { return static_cast<uint32_t>(height.size()); }
};

/// Samples `result` from every vertex of `clean` (threads: 0 = all). A vertex without a normal
/// (no incident area) weighs nothing: height 0, no hit. Empty when either mesh has no triangles.
SurfaceSample sample_surface(const MeshView& clean, const MeshView& result, int threads = 0);

/// Area-weighted RMS of the heights (clean mean edges); NaN without area.
double height_rms(const SurfaceSample& s);
/// Area-weighted mean angle between n_r and n_c (radians); NaN without area.
double smooth_normal_error(const SurfaceSample& s);
/// SF between two frames (clean mean edges, weighted by `now`'s areas); NaN when the clean
/// frames differ in vertex count or have no area.
double surface_flicker(const SurfaceSample& before, const SurfaceSample& now);
/// ShF between two frames (chord length of unit vectors, about radians); NaN as surface_flicker.
double shading_flicker(const SurfaceSample& before, const SurfaceSample& now);

/// One frame's surface measures; the pair measures are absent on a sequence's first frame and
/// where the clean frames do not share their vertices.
struct SurfaceFrameMetrics {
  double height_rms = 0.0;
  double smooth_normal_error = 0.0;
  std::optional<double> surface_flicker, shading_flicker;
};

/// A sequence's surface measures, frame by frame, and their means (the pair measures averaged
/// over transitions).
class SurfaceFlickerSeries {
 public:
  /// Measures `sample` against the frame before (kept from the last call) and keeps it.
  SurfaceFrameMetrics add(SurfaceSample sample);
  /// Forgets the frame before (the next frame starts a new sequence).
  void reset() { before_.reset(); }

  double mean_height_rms() const { return mean(height_rms_); }
  double mean_smooth_normal_error() const { return mean(normal_error_); }
  double mean_surface_flicker() const { return mean(surface_flicker_); }
  double mean_shading_flicker() const { return mean(shading_flicker_); }
  size_t frames() const { return height_rms_.size(); }
  size_t transitions() const { return surface_flicker_.size(); }

 private:
  static double mean(const std::vector<double>& x);

  std::optional<SurfaceSample> before_;
  std::vector<double> height_rms_, normal_error_, surface_flicker_, shading_flicker_;
};

}  // namespace fq
