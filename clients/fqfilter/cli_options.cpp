#include "clients/fqfilter/cli_options.h"

#include <CLI/CLI.hpp>
#include <filesystem>
#include <iostream>

#include "clients/common/defaulted_option.h"
#include "clients/common/tool_app.h"
#include "clients/fqfilter/param_options.h"

namespace fq::cli {

namespace {

using client::add_defaulted;
using client::add_ranged;

// The parameter groups below are added after app.option_defaults()->always_capture_default():
// every option shows its default in --help; option_defaults()->group() names the group.

void add_parameter_groups(CLI::App& app, Options& o, bool& no_filter) {
  app.option_defaults()->group("Filter");
  add_param_options(app, o.params, ParamGroup::kFilter);
  app.option_defaults()->group("Noise (--mode qf+)");
  add_param_options(app, o.params, ParamGroup::kNoise);
  app.option_defaults()->group("Sequence (--mode qf+)");
  app.add_flag("--sequence", o.sequence,
               "IN is a folder of one stream's frames: filter them in name order, each with the last "
               "result as evidence (as fqd does with temporal > 0), noise seeded by --seed + frame index, "
               "flicker reported");
  add_param_options(app, o.params, ParamGroup::kTemporal);
  app.get_option("--temporal")
      ->default_str(format_param(*find_param("temporal"), kDefaultTemporal) + " with --sequence");
  app.option_defaults()->group("Clustering");
  add_param_options(app, o.params, ParamGroup::kCompute);
  app.add_flag(
      "--colour-clusters", o.colour_clusters,
      "Cluster colours replace the input's vertex colours (default: they go to cluster_red/green/blue)");
  app.add_flag("--no-filter", no_filter, "Cluster only: keep the input positions (implies --cluster)");
  add_param_options(app, o.params, ParamGroup::kCluster);
}

void add_run_options(CLI::App& app, Options& o, std::string& engine, std::string& noise_kind) {
  app.add_option("IN", o.input, "Mesh file (.ply .obj .stl .drc) or folder of them")->required();
  app.add_option("OUT", o.output,
                 "Output file (.ply .drc .obj .glb), or folder when IN is a folder; none: write nothing");
  app.add_flag("--in-place", o.in_place,
               "Allow OUT to be IN: the input is replaced once the result is written");
  app.add_flag("--keep-normals", o.keep_normals,
               "Write the input's normals unchanged (default: recomputed from the filtered surface, an "
               "OBJ's per-corner normals within their groups, so hard edges stay hard)");
  add_defaulted(app, "--engine", engine, "auto (CUDA when a GPU is present), cpu or cuda")
      ->check(CLI::IsMember({"auto", "cpu", "cuda"}));
  add_ranged(app, "--threads", o.engine.threads, "CPU engine threads; 0 = all hardware threads", 0, 4096);
  app.add_option("--noise", o.noise_sigma,
                 "Add Gaussian noise of this std (mean edge lengths) before filtering")
      ->check(CLI::Range(0.0, 100.0));
  add_defaulted(
      app, "--noise-kind,--noise-direction", noise_kind,
      "iso: every coordinate; normal: along the clean mesh's vertex normals; depth: a range scanner's "
      "along z, growing at grazing angles; correlated: along the normals, correlated over --noise-length; "
      "ripple: scan-line stripes along x of period --noise-length (docs/QUALITY.md)")
      ->check(CLI::IsMember({"iso", "normal", "depth", "correlated", "ripple"}));
  add_ranged(app, "--noise-length", o.noise_length,
             "--noise-kind correlated: the correlation length; ripple: the period (mean edge lengths)", 0.1,
             100.0);
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
  if (o.repeat > 1)
    return "--sequence runs each frame once (--repeat would filter a frame with its own result)";
  return "";
}

}  // namespace

ParseOutcome parse_options(int argc, char** argv, Options& o) {
  client::ToolApp app{"fqfilter: smooth and cluster meshes with filtered quadrics (Legrand et al. 2019)",
                      "fqfilter"};
  app.name("fqfilter");  // "Usage: fqfilter", whatever path it was started by
  app.footer(kExamples);
  std::string engine = "auto";
  bool no_filter = false;
  std::string noise_kind = "iso";
  add_run_options(app, o, engine, noise_kind);
  app.option_defaults()->always_capture_default();
  add_parameter_groups(app, o, no_filter);
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {  // --help, --version
    return {false, app.exit(e)};
  } catch (const CLI::ParseError& e) {
    std::cerr << "fqfilter: error: " << e.what() << " (see fqfilter --help)\n";
    return {false, 2};
  }
  parse_engine_kind(engine, o.engine.kind);
  parse_noise_kind(noise_kind.c_str(), o.noise_kind);  // one of the names the check allowed
  if (no_filter) {
    o.params.filter = false;
    o.params.cluster = true;
  }
  if (const std::string why = check_sequence(o, app.count("--temporal") > 0); !why.empty()) {
    std::cerr << "fqfilter: error: " << why << "\n";
    return {false, 2};
  }
  if (o.sequence && app.count("--temporal") == 0) o.params.filtering.temporal = kDefaultTemporal;
  if (const std::string why = check_params(o); !why.empty()) {
    std::cerr << "fqfilter: error: " << why << "\n";
    return {false, 2};
  }
  return {true, 0};
}

}  // namespace fq::cli
