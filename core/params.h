// Parameters of the filter and the clustering. Every sigma is in units of the frame's
// mean edge length, as in the paper; neighbourhoods have radius 2 sigma.
#pragma once

#include <cstdint>

#include "common/status.h"

namespace fq {

/// "qf+" (fq's noise-adaptive filter, RefineParams below; the default) | "qf" (the paper's
/// filtered quadrics, exactly) | "bf" (Jones 2003).
enum class FilterMethod { kQuadric, kBilateral, kQuadricRefined };
enum class ClusterMethod { kQuadric, kEuclidean };  ///< the paper | plain quick shift (Fig. 17)
/// Whose quadrics the clustering scores and links with: the input's (the paper) or those
/// of the mesh after a normal-constrained filter, at half the filter's sigma_s and sigma_r
/// (docs/ALGORITHM.md). kAuto: filtered with a target cluster count, input otherwise.
enum class ClusterGeometry { kAuto, kInput, kFiltered };

/// "qf+", fq's default filter: it estimates each frame's noise from the frame itself
/// (kernels/noise_estimate.h) and derives every strength from it (kernels/refine_plan.h), so a
/// frame with half the noise gets about half the smoothing and a clean frame almost none; see
/// docs/ALGORITHM.md, "qf+: a filter that follows the noise". Both values are optional.
struct RefineParams {
  /// The noise to filter for, in mean edge lengths (standard deviation along the surface
  /// normal); 0: estimated per frame. Set it when a capture rig's noise is known, or to force a
  /// full filter on an input the estimate finds clean.
  float known_noise = 0.f;
  /// Multiplies the noise (estimated or given) that the strengths are derived from: 2 filters
  /// as for twice the noise, 0.5 as for half, 0 not at all.
  float strength = 1.f;
};

/// The temporal strength fqfilter --sequence and a stream with `temporal = true` use
/// (FilterParams::temporal; docs/ALGORITHM.md, "Temporal filtering").
inline constexpr float kDefaultTemporal = 0.75f;

struct FilterParams {
  FilterMethod method = FilterMethod::kQuadricRefined;
  /// The quadric diffusion's extents, for "qf" and for the clustering (which scores the same
  /// filtered quadrics); "qf+" moves vertices without them. Defaults 1.5 / 0.7 (the paper's
  /// Table 1 uses 2 / 1 and 2 / 0.7; pass them for the paper's rows).
  float sigma_s = 1.5f;      ///< spatial extent of the quadric diffusion (BF: of the filter)
  float sigma_r = 0.7f;      ///< range extent (RMS quadric distance; BF: prediction distance)
  float sigma_b = 0.0f;      ///< finest detail captured by Q'; 0 means sigma_s / 2
  float sigma_n = 0.0f;      ///< normal smoothing for constrained mode; 0 means sigma_s / 2
  bool constrained = false;  ///< move along the smoothed normal instead of to the minimizer
  /// Tikhonov pull toward the current position, relative to tr(A)/3. 0.05 keeps a clean
  /// mesh intact and improves noisy ones (see docs/QUALITY.md); 0 is the paper's solver.
  float tikhonov = 0.05f;
  RefineParams refine;  ///< used by "qf+" only
  /// "qf+" on a stream whose engine holds its history (Engine::set_history): how far each
  /// vertex may be pulled to the last result's surface where that surface did not move, in
  /// [0, 1]; 0: each frame alone (docs/ALGORITHM.md, "Temporal filtering").
  float temporal = 0.f;

  /// Whether the filter moves vertices with the filtered quadrics ("qf" only).
  bool uses_quadrics() const { return method == FilterMethod::kQuadric; }

  float effective_sigma_b() const { return sigma_b > 0.f ? sigma_b : 0.5f * sigma_s; }
  float effective_sigma_n() const { return sigma_n > 0.f ? sigma_n : 0.5f * sigma_s; }
};

struct ClusterParams {
  ClusterMethod method = ClusterMethod::kQuadric;
  float sigma_d = 5.0f;  ///< spatial extent of score and proximity
  float sigma_q = 1.0f;  ///< range extent (RMS quadric distance)
  float theta = 0.9f;    ///< in (0, 1]; higher gives fewer, larger clusters (cut p < 1 - theta)
  /// > 0: theta is chosen per frame to give the cluster count closest to this (theta ignored).
  uint32_t target_clusters = 0;
  ClusterGeometry geometry = ClusterGeometry::kAuto;
  ClusterGeometry effective_geometry() const {
    if (geometry != ClusterGeometry::kAuto) return geometry;
    return target_clusters > 0 ? ClusterGeometry::kFiltered : ClusterGeometry::kInput;
  }
  /// > 0: labels are split into mesh-connected parts and parts under this many vertices are
  /// merged into the neighbour they share most edges with; 0: the paper's labels.
  uint32_t min_cluster_size = 0;
  /// fqd only (engines ignore them): keep cluster ids stable from frame to frame of a stream,
  /// and how many edge rings a border may move back to the previous frame's (0: none; the
  /// per-vertex vote over the last frames, kernels/label_tracking.h, holds borders without it).
  bool track_ids = true;
  uint32_t sticky_rings = 0;
  /// Also return the link forest before the theta cut (FrameResult::link_parent, link_p).
  bool keep_links = false;
};

struct Params {
  bool filter = true;        ///< move the vertices
  bool cluster = false;      ///< compute labels (on the input positions, from the same Q^bl)
  FilterParams filtering;    ///< the filter's parameters
  ClusterParams clustering;  ///< the clustering's parameters
};

/// Clear message for the first bad value (sigma <= 0, NaN, theta outside (0, 1], ...): each
/// row of the parameter table (core/param_table.h) checked against its range; the clustering's
/// rows only with `cluster`.
Status validate(const Params& p);

}  // namespace fq
