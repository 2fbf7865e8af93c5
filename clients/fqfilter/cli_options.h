// fqfilter's command line: every option, its default and its checks (CLI11).
#pragma once

#include <cstdint>
#include <string>

#include "core/params.h"
#include "eval/noise.h"
#include "kernels/engine.h"

namespace fq::cli {

struct Options {
  std::string input;   ///< a mesh file or a folder of them
  std::string output;  ///< file (.ply/.drc/.obj/.glb) or folder; empty: write nothing
  EngineOptions engine;
  Params params;                           ///< defaults from fq::Params
  double noise_sigma = 0;                  ///< in mean edge lengths; 0: no noise
  NoiseKind noise_kind = NoiseKind::kIso;  ///< --noise-kind
  double noise_length = 2.0;               ///< --noise-length: correlation length or ripple period
  std::string noisy_out;                   ///< also write the noisy input here (.ply/.drc); empty: don't
  uint64_t seed = 1;
  std::string reference;     ///< clean mesh for the metrics; empty: the input when noise is added
  std::string cuda_refused;  ///< --engine auto fell back to the CPU: why (make_engine), for the report
  int repeat = 1;            ///< engine runs per frame; timings are medians
  int drc_bits = 16;         ///< position quantization of .drc outputs
  bool json = false;
  bool quiet = false;  ///< no report table, progress line or per-file line; warnings and errors stay
  bool colour_clusters = false;  ///< cluster colours replace the input's vertex colours
  bool in_place = false;         ///< OUT may be IN itself (replaced once the result is written)
  bool keep_normals = false;     ///< write the input's normals as they were, not the filtered surface's
  bool sequence = false;  ///< IN is a folder of one stream's frames, filtered in name order with its history
};

/// Outcome of parsing: run, or exit with `exit_code` (help printed, or an error line).
struct ParseOutcome {
  bool run = false;
  int exit_code = 0;
};

/// Parses argv into `out`. Prints help to stdout, or one "fqfilter: error: ..." line to
/// stderr (exit code 2) for a bad option, a bad value or inconsistent options.
ParseOutcome parse_options(int argc, char** argv, Options& out);

}  // namespace fq::cli
