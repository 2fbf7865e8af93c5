#include "clients/fqfilter/cli_options.h"

#include <CLI/CLI.hpp>
#include <filesystem>
#include <iostream>

#include "clients/common/defaulted_option.h"
#include "clients/common/member_options.h"
#include "clients/common/tool_app.h"

namespace fq::cli {

namespace {

using client::add_defaulted;
using client::add_member_options;
using client::add_ranged;
using client::MemberOption;

// Every member of RefineParams, in --help's order: one option a row, its help under its flag.
// clang-format off
const MemberOption<RefineParams> kRefineOptions[] = {
    {"--known-noise", &RefineParams::known_noise,
     "Noise to filter for, in mean edge lengths (along the normal); 0 = estimated per mesh"},
    {"--strength", &RefineParams::strength,
     "Multiplies the noise the filter's strengths come from (2: as for twice the noise; 0: no filtering)"},
};
// clang-format on

// The groups below are added after app.option_defaults()->always_capture_default(): every
// option of theirs shows its default in --help; option_defaults()->group() names the group.

void add_filter_options(CLI::App& app, Options& o, std::string& mode) {
  FilterParams& f = o.params.filtering;
  app.option_defaults()->group("Filter");
  app.add_option("--mode", mode,
                 "Filter: qf+ (fq's filter, its strength derived from the noise it estimates), qf (the "
                 "paper's filtered quadrics exactly) or bf (bilateral baseline)")
      ->check(CLI::IsMember(method_names<FilterMethod>()));
  app.add_option("--sigma-s", f.sigma_s, "qf, bf and the clustering: spatial extent of the diffusion, in mean edge lengths");
  app.add_option("--sigma-r", f.sigma_r, "qf and the clustering: range extent (RMS quadric distance), in mean edge lengths");
  app.add_option("--sigma-b", f.sigma_b,
                 "Finest detail captured by the neighbourhood quadrics; 0 = sigma-s/2");
  app.add_option("--sigma-n", f.sigma_n, "Normal smoothing of --constrained; 0 = sigma-s/2");
  app.add_flag("--constrained", f.constrained, "Move vertices along the smoothed normal only");
  app.add_option("--tikhonov", f.tikhonov,
                 "Pull toward the current position, relative to tr(A)/3; 0 = paper");
}

void add_refine_options(CLI::App& app, RefineParams& r) {
  app.option_defaults()->group("Noise (--mode qf+)");
  add_member_options(app, r, kRefineOptions);
}

/// Filtering across frames; the default strength applies with --sequence only.
void add_sequence_options(CLI::App& app, Options& o, float& temporal) {
  app.option_defaults()->group("Sequence (--mode qf+)");
  app.add_flag("--sequence", o.sequence,
               "IN is a folder of one stream's frames: filter them in name order, each with the last "
               "result as evidence (as fqd does with temporal > 0), noise seeded by --seed + frame index, "
               "flicker reported");
  app.add_option("--temporal", temporal,
                 "With --sequence: how far a vertex may be pulled to the last result's surface where "
                 "that surface did not move, in [0, 1]; 0 = each frame alone")
      ->check(CLI::Range(0.0, 1.0));
}

void add_cluster_control_options(CLI::App& app, Options& o, std::string& geometry) {
  ClusterParams& c = o.params.clustering;
  app.option_defaults()->group("Clustering");
  app.add_option("--target-clusters", c.target_clusters,
                 "Choose theta per mesh to give about K clusters (0 = use --theta)");
  app.add_option("--cluster-geometry", geometry,
                 "Quadrics the clustering uses: input (the paper), filtered (after a constrained filter) or "
                 "auto (filtered with --target-clusters)")
      ->check(CLI::IsMember(cluster_geometry_names()));
  app.add_option("--min-cluster-size", c.min_cluster_size,
                 "Split clusters into mesh-connected parts and merge parts under N vertices (0 = off)");
}

void add_cluster_options(CLI::App& app, Options& o, std::string& method, bool& no_filter) {
  ClusterParams& c = o.params.clustering;
  app.option_defaults()->group("Clustering");
  app.add_flag("--cluster", o.params.cluster, "Compute a cluster label per vertex (written with the output)");
  app.add_flag(
      "--colour-clusters", o.colour_clusters,
      "Cluster colours replace the input's vertex colours (default: they go to cluster_red/green/blue)");
  app.add_flag("--no-filter", no_filter, "Cluster only: keep the input positions (implies --cluster)");
  app.add_option("--cluster-method", method, "quadric (the paper) or euclidean (plain quick shift)")
      ->check(CLI::IsMember(method_names<ClusterMethod>()));
  app.add_option("--sigma-d", c.sigma_d, "Spatial extent of score and proximity, in mean edge lengths");
  app.add_option("--sigma-q", c.sigma_q, "Range extent of the clustering (RMS quadric distance)");
  app.add_option("--theta", c.theta, "In (0, 1]; higher gives fewer, larger clusters");
}

void add_run_options(CLI::App& app, Options& o, std::string& engine, std::string& noise_direction) {
  app.add_option("IN", o.input, "Mesh file (.ply .obj .stl .drc) or folder of them")->required();
  app.add_option("OUT", o.output,
                 "Output file (.ply .drc .obj .glb), or folder when IN is a folder; none: write nothing");
  app.add_flag("--in-place", o.in_place,
               "Allow OUT to be IN: the input is replaced once the result is written");
  add_defaulted(app, "--engine", engine, "auto (CUDA when a GPU is present), cpu or cuda")
      ->check(CLI::IsMember({"auto", "cpu", "cuda"}));
  add_ranged(app, "--threads", o.engine.threads, "CPU engine threads; 0 = all hardware threads", 0, 4096);
  app.add_option("--noise", o.noise_sigma,
                 "Add Gaussian noise of this std (mean edge lengths) before filtering")
      ->check(CLI::Range(0.0, 100.0));
  add_defaulted(app, "--noise-direction", noise_direction,
                "iso: every coordinate; normal: along the clean mesh's vertex normals")
      ->check(CLI::IsMember({"iso", "normal"}));
  add_defaulted(app, "--seed", o.seed, "Seed of --noise");
  app.add_option("--noisy-out", o.noisy_out,
                 "Also write the noisy input mesh to this file (to run other smoothers on the same input)");
  app.add_option("--reference", o.reference,
                 "Clean mesh (same vertices and faces) to measure errors against");
  add_ranged(app, "--repeat", o.repeat, "Run the engine N times per mesh; timings are medians", 1, 100000);
  add_ranged(app, "--drc-bits", o.drc_bits, "Position quantization bits of .drc outputs (0 = lossless)", 0,
             30);
  app.add_flag("--json", o.json, "One JSON object per mesh on stdout (see docs/FQFILTER.md)");
  app.add_flag("--quiet,-q", o.quiet,
               "Print only warnings, errors and a folder's closing line (no report table or progress)");
}

// --help ends with these: the three commands most runs are.
constexpr const char* kExamples = R"(Examples:
  fqfilter scan.ply scan_smooth.ply                        smooth a mesh (qf+, the default)
  fqfilter scans/ smoothed/ --quiet                        a folder of meshes; only problems printed
  fqfilter part.obj part.glb --cluster --colour-clusters   clusters as colours, for a glTF viewer)";

/// fq::validate of the parsed parameters (CLI11 checks each option alone: not NaN, theta
/// in (0, 1], nothing to compute); the message, empty when valid.
std::string check_params(const Options& o) { return validate(o.params).message(); }

/// What --sequence and --temporal need of the other options; the message, empty when fine.
std::string check_sequence(const Options& o, bool temporal_given) {
  if (temporal_given && !o.sequence) return "--temporal needs --sequence (frames of one stream)";
  if (!o.sequence) return "";
  std::error_code ec;
  if (!std::filesystem::is_directory(o.input, ec)) return "--sequence needs a folder of frames as IN";
  if (o.params.filter && o.params.filtering.method != FilterMethod::kQuadricRefined)
    return "--sequence filters across frames with --mode qf+ only";
  if (o.repeat > 1) return "--sequence runs each frame once (--repeat would filter a frame with its own result)";
  return "";
}

}  // namespace

ParseOutcome parse_options(int argc, char** argv, Options& o) {
  client::ToolApp app{"fqfilter: smooth and cluster meshes with filtered quadrics (Legrand et al. 2019)",
                      "fqfilter"};
  app.name("fqfilter");  // "Usage: fqfilter", whatever path it was started by
  app.footer(kExamples);
  std::string mode = method_name(o.params.filtering.method), method = method_name(o.params.clustering.method), engine = "auto",
              geometry = "auto";
  bool no_filter = false;
  std::string noise_direction = "iso";
  add_run_options(app, o, engine, noise_direction);
  app.option_defaults()->always_capture_default();
  add_filter_options(app, o, mode);
  add_refine_options(app, o.params.filtering.refine);
  float temporal = kDefaultTemporal;
  add_sequence_options(app, o, temporal);
  add_cluster_options(app, o, method, no_filter);
  add_cluster_control_options(app, o, geometry);
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {  // --help, --version
    return {false, app.exit(e)};
  } catch (const CLI::ParseError& e) {
    std::cerr << "fqfilter: error: " << e.what() << " (see fqfilter --help)\n";
    return {false, 2};
  }
  // CLI::IsMember has accepted only known names.
  o.params.filtering.method = *parse_method<FilterMethod>(mode);
  o.params.clustering.method = *parse_method<ClusterMethod>(method);
  parse_cluster_geometry(geometry, o.params.clustering.geometry);  // checked by IsMember above
  parse_engine_kind(engine, o.engine.kind);
  o.noise_along_normal = noise_direction == "normal";
  if (no_filter) {
    o.params.filter = false;
    o.params.cluster = true;
  }
  if (const std::string why = check_sequence(o, app.count("--temporal") > 0); !why.empty()) {
    std::cerr << "fqfilter: error: " << why << "\n";
    return {false, 2};
  }
  if (o.sequence) o.params.filtering.temporal = temporal;
  if (const std::string why = check_params(o); !why.empty()) {
    std::cerr << "fqfilter: error: " << why << "\n";
    return {false, 2};
  }
  return {true, 0};
}

}  // namespace fq::cli
