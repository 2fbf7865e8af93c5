// What fqfilter measured for one mesh, printed as a table or as one JSON object.
#pragma once

#include <array>
#include <cstdint>
#include <iosfwd>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/params.h"
#include "eval/error_metrics.h"
#include "eval/flicker.h"
#include "eval/noise.h"
#include "eval/sharp_edge_recall.h"
#include "eval/surface_distance.h"
#include "eval/surface_flicker.h"
#include "eval/vertex_moves.h"
#include "kernels/engine.h"

namespace fq::cli {

/// Error of one vertex set against the reference.
struct MeshError {
  double rmse_over_diagonal = 0.0;  ///< vertex to vertex (counts sliding along the surface)
  SurfaceDistance surface;          ///< vertex to the reference surface (does not)
  MfneResult mfne;
};

struct FileReport {
  std::string file;
  std::string output;        ///< written file; empty when none
  std::string engine;        ///< Engine::name()
  std::string cuda_refused;  ///< --engine auto ran on the CPU: why CUDA was not used (empty otherwise)
  int threads = 0;           ///< CPU engine threads; 0 for other engines
  uint32_t vertices = 0;
  uint32_t triangles = 0;
  double mean_edge = 0.0;  ///< of the engine's input, in input units
  Params params;
  double noise_sigma = 0.0;
  NoiseKind noise_kind = NoiseKind::kIso;
  double noise_length = 0.0;
  uint64_t seed = 0;
  int repeat = 1;
  std::vector<PassTiming> passes;  ///< median ms of each pass over the repeats
  double total_ms = 0.0;           ///< median of the per-run totals
  /// "qf+": the noise estimated from the mesh and the noise filtered for (mean edge lengths).
  std::optional<float> noise_estimate, filter_noise;
  /// "qf+": the residual the estimate was read from (the rest of it taken for detail).
  std::optional<float> noise_residual;
  /// "qf+": noise along one direction the frame shares (mean edge lengths; 0: none found), its
  /// unit direction and the RMS of n·d (kernels/noise_estimate.h, NoiseEstimate).
  std::optional<float> noise_directional;
  std::array<float, 3> noise_direction{};
  float noise_alignment = 0.f;
  /// How far the filter moved the vertices (mean edge lengths); absent without filtering.
  std::optional<VertexMoves> moved;
  /// Coincident vertices (seam twins) filtered as one with their first copy (kernels/seam_weld.h).
  uint32_t welded_vertices = 0;
  /// --sequence: the share of vertices that found a prior in the last result, the mean pull
  /// towards it, whether this frame reset the stream's history (a scene cut), and the flicker
  /// against the last frame (eval/flicker.h; with a reference of the same vertices), split
  /// along the clean normals and across them.
  std::optional<float> prior_coverage, prior_share;
  bool history_reset = false;
  /// Which temporal track ran ("ids", "space" or "none": kernels/engine.h), and whether the
  /// ids were refused (same connectivity, but they did not follow a smooth motion).
  const char* temporal_track = "none";
  bool ids_refused = false;
  std::optional<float> ids_wide;  ///< track A's mean share of the wide motion estimate
  std::optional<double> flicker;
  std::optional<FlickerParts> flicker_parts;
  /// --sequence with a reference: the result's surface seen from the clean frame's vertices
  /// (eval/surface_flicker.h): height RMS, smooth-normal error, and SF and ShF against the
  /// last frame.
  std::optional<SurfaceFrameMetrics> surface;
  std::optional<uint32_t> clusters;
  std::optional<float> theta_used;             ///< the theta that gave the labels (found with a target)
  std::optional<SharpEdgeRecall> sharp_edges;  ///< labels vs the reference's creases
  std::string reference;                       ///< what the metrics compare to; empty: no metrics
  std::optional<MeshError> input_error;        ///< engine input (noisy) vs reference
  std::optional<MeshError> output_error;       ///< result vs reference (when filtering)
  std::vector<std::string> warnings;           ///< what the output could not keep of the input
  std::string error;                           ///< non-empty when the file failed
};

/// Per pass (by name, in the first run's order) the median over runs, and the median total.
void summarize_timings(const std::vector<std::vector<PassTiming>>& runs, FileReport& report);

/// Below this estimated noise (mean edge lengths) the report calls an input clean: what "qf+" then
/// does is a light touch (docs/ALGORITHM.md), and the report names the option for a full filter.
inline constexpr float kLooksCleanBelow = 0.02f;
/// Below this estimated noise the report says the input was read as lightly noisy and names
/// --strength: a raw range scan's correlated noise reads about 0.05 (docs/QUALITY.md, "Real
/// scans"), and a user who sees "the output looks the same" should see why and what to turn.
inline constexpr float kReadsLightBelow = 0.1f;

/// The JSON object documented in docs/FQFILTER.md (NaN values become null).
nlohmann::json to_json(const FileReport& report);

/// Compact human-readable table: header line, pass timings, clusters, metrics.
void print_human(const FileReport& report, std::ostream& os);

}  // namespace fq::cli
