#include "clients/fqfilter/folder_mode.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>

#include "clients/fqfilter/file_job.h"
#include "io/mesh_io.h"

namespace fq::cli {

namespace fs = std::filesystem;

namespace {

/// Creates the output folder; refuses the input folder itself (outputs would replace inputs).
bool prepare_output_folder(const Options& o) {
  std::error_code ec;
  if (fs::exists(o.output, ec) && !fs::is_directory(o.output, ec)) {
    std::cerr << "fqfilter: error: OUT '" << o.output
              << "' is a file; with a folder as IN, OUT must be a folder\n";
    return false;
  }
  fs::create_directories(o.output, ec);
  if (ec) {
    std::cerr << "fqfilter: error: cannot create output folder '" << o.output << "': " << ec.message()
              << "\n";
    return false;
  }
  if (fs::equivalent(o.input, o.output, ec)) {
    std::cerr << "fqfilter: error: OUT must differ from IN (outputs would overwrite the inputs)\n";
    return false;
  }
  return true;
}

void print_report(const Options& o, const FileReport& r) {
  if (o.json)
    std::cout << to_json(r).dump() << std::endl;
  else if (r.error.empty() && !o.quiet)
    print_human(r, std::cout);
}

}  // namespace

std::vector<fs::path> list_mesh_files(const fs::path& folder) {
  std::vector<fs::path> files;
  for (const fs::directory_entry& e : fs::directory_iterator(folder)) {
    if (e.is_regular_file() && io::is_readable_mesh_file(e.path().string())) files.push_back(e.path());
  }
  std::sort(files.begin(), files.end(),
            [](const fs::path& a, const fs::path& b) { return a.filename() < b.filename(); });
  return files;
}

int run_folder(const Options& o, Engine& engine) {
  if (!o.output.empty() && !prepare_output_folder(o)) return 2;
  const std::vector<fs::path> files = list_mesh_files(o.input);
  if (files.empty()) {
    std::cerr << "fqfilter: error: no .ply, .obj, .stl or .drc files in '" << o.input << "'\n";
    return 1;
  }
  std::map<std::string, std::string> claimed;  // output name -> input that writes it
  size_t failed = 0;
  for (size_t i = 0; i < files.size(); ++i) {
    const std::string name = files[i].filename().string();
    const std::string out_name = files[i].stem().string() + ".ply";
    std::string output = o.output.empty() ? "" : (fs::path(o.output) / out_name).string();
    FileReport report;
    Status s;
    if (!output.empty() && claimed.count(out_name)) {
      s = io_error("output '" + output + "' would also be written by " + claimed[out_name]);
      report.file = files[i].string();
      report.error = s.message();
    } else {
      claimed[out_name] = name;
      s = run_file_job(files[i].string(), output, o, engine, report);
    }
    if (!s.ok()) ++failed;
    if (!s.ok() || !o.quiet) {
      std::cerr << "[" << (i + 1) << "/" << files.size() << "] " << name << ": ";
      if (s.ok())
        std::cerr << report.vertices << " V, " << std::lround(report.total_ms) << " ms\n";
      else
        std::cerr << "FAILED: " << s.message() << "\n";
    }
    print_report(o, report);
  }
  std::cerr << "fqfilter: " << (files.size() - failed) << " of " << files.size() << " files done";
  if (failed) std::cerr << ", " << failed << " failed";
  std::cerr << "\n";
  return failed ? 1 : 0;
}

}  // namespace fq::cli
