// Parameters of the filter and the clustering. Every sigma is in units of the frame's
// mean edge length, as in the paper; neighbourhoods have radius 2 sigma.
#pragma once

#include <string>

#include "common/status.h"

namespace fq {

enum class FilterMethod { kQuadric, kBilateral };   ///< "qf" (the paper) | "bf" (Jones 2003)
enum class ClusterMethod { kQuadric, kEuclidean };  ///< the paper | plain quick shift (Fig. 17)
/// Whose quadrics the clustering scores and links with: the input's (the paper) or those
/// of the mesh after a normal-constrained filter, at half the filter's sigma_s and sigma_r
/// (docs/ALGORITHM.md). kAuto: filtered with a target cluster count, input otherwise.
enum class ClusterGeometry { kAuto, kInput, kFiltered };

struct FilterParams {
  FilterMethod method = FilterMethod::kQuadric;
  float sigma_s = 2.0f;  ///< spatial extent of the quadric diffusion (BF: of the filter)
  float sigma_r = 1.0f;  ///< range extent (RMS quadric distance; BF: prediction distance)
  float sigma_b = 0.0f;  ///< finest detail captured by Q'; 0 means sigma_s / 2
  float sigma_n = 0.0f;  ///< normal smoothing for constrained mode; 0 means sigma_s / 2
  bool constrained = false;  ///< move along the smoothed normal instead of to the minimizer
  /// Tikhonov pull toward the current position, relative to tr(A)/3. 0.05 keeps a clean
  /// mesh intact and improves noisy ones (see docs/QUALITY.md); 0 is the paper's solver.
  float tikhonov = 0.05f;

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
  /// and how many edge rings a border may move back to the previous frame's (0: ids only).
  bool track_ids = true;
  uint32_t sticky_rings = 2;
  /// Also return the link forest before the theta cut (FrameResult::link_parent, link_p).
  bool keep_links = false;
};

struct Params {
  bool filter = true;    ///< move the vertices
  bool cluster = false;  ///< compute labels (on the input positions, from the same Q^bl)
  FilterParams f;
  ClusterParams c;
};

/// "auto" | "input" | "filtered" (command lines, config files).
bool parse_cluster_geometry(const std::string& s, ClusterGeometry& out);
const char* cluster_geometry_name(ClusterGeometry g);

/// Clear message for the first bad value (sigma <= 0, NaN, theta outside (0, 1], ...).
Status validate(const Params& p);

}  // namespace fq
