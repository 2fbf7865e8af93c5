// fqfilter: offline front end of the fq engines. See docs/FQFILTER.md.
#include <exception>
#include <filesystem>
#include <iostream>

#include "clients/fqfilter/cli_options.h"
#include "clients/fqfilter/file_job.h"
#include "clients/fqfilter/folder_mode.h"
#include "common/tool_main.h"
#include "io/mesh_io.h"
#include "kernels/engine.h"

namespace {

namespace fs = std::filesystem;
using fq::cli::Options;

/// Output path for a single input: OUT itself, or OUT/<name>.ply when OUT is a folder.
std::string single_output_path(const Options& o) {
  std::error_code ec;
  if (!o.output.empty() && fs::is_directory(o.output, ec))
    return (fs::path(o.output) / (fs::path(o.input).stem().string() + ".ply")).string();
  return o.output;
}

int run_single(const Options& o, fq::Engine& engine) {
  const std::string output = single_output_path(o);
  if (!output.empty() && !fq::io::is_writable_mesh_file(output)) {
    std::cerr << "fqfilter: error: OUT '" << output << "' must end in .ply, .drc, .obj or .glb\n";
    return 2;
  }
  if (!output.empty() && !o.in_place && fq::cli::is_same_file(o.input, output)) {
    std::cerr << "fqfilter: error: OUT '" << output << "' is the input file; pass --in-place to replace it\n";
    return 2;
  }
  fq::cli::FileReport report;
  const fq::Status s = fq::cli::run_file_job(o.input, output, o, engine, report);
  if (o.json) std::cout << fq::cli::to_json(report).dump() << std::endl;
  if (!s.ok()) {
    std::cerr << "fqfilter: error: " << s.message() << "\n";
    return 1;
  }
  if (!o.json && !o.quiet) fq::cli::print_human(report, std::cout);
  return 0;
}

int run(int argc, char** argv) {
  Options o;
  const fq::cli::ParseOutcome parsed = fq::cli::parse_options(argc, argv, o);
  if (!parsed.run) return parsed.exit_code;
  std::error_code ec;
  if (!fs::exists(o.input, ec)) {  // named as IN's problem, not as a bad OUT
    std::cerr << "fqfilter: error: IN '" << o.input << "': no such file or folder\n";
    return 2;
  }
  const bool folder = fs::is_directory(o.input, ec);
  if (!folder && !o.reference.empty() && fs::is_directory(o.reference, ec)) {
    std::cerr << "fqfilter: error: --reference must be a mesh file\n";
    return 2;
  }
  if (folder && !o.reference.empty()) {
    std::cerr << "fqfilter: error: --reference needs a single input file, not a folder\n";
    return 2;
  }
  const fq::StatusOr<std::unique_ptr<fq::Engine>> engine = fq::make_engine(o.engine, &o.cuda_refused);
  if (!engine.ok()) {
    std::cerr << "fqfilter: error: " << engine.status().message() << "\n";
    return 1;
  }
  return folder ? fq::cli::run_folder(o, **engine) : run_single(o, **engine);
}

}  // namespace

int main(int argc, char** argv) { return fq::tool_main("fqfilter", run, argc, argv); }
