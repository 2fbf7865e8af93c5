#include "clients/fqfilter/folder_mode.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <optional>
#include <utility>

#include "clients/fqfilter/file_job.h"
#include "eval/flicker.h"
#include "eval/surface_flicker.h"
#include "io/mesh_io.h"
#include "kernels/temporal.h"

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

namespace {

/// --sequence: what the closing line says about the whole stream.
struct SequenceSummary {
  double mfne_sum = 0.0, flicker_sum = 0.0;
  size_t mfne_frames = 0, flicker_frames = 0, resets = 0;
  SurfaceFlickerSeries surface;  // the surface measures of every frame with a reference

  void add(const FileReport& r) {
    if (r.output_error && std::isfinite(r.output_error->mfne.mean_radians)) {
      mfne_sum += r.output_error->mfne.mean_radians;
      ++mfne_frames;
    }
    if (r.flicker) {
      flicker_sum += *r.flicker;
      ++flicker_frames;
    }
    resets += r.history_reset ? 1 : 0;
  }
  void print(std::ostream& os) const {
    os << "fqfilter: sequence: " << resets << " scene cut" << (resets == 1 ? "" : "s");
    if (mfne_frames) os << ", mean MFNE " << mfne_sum / double(mfne_frames) << " rad";
    if (flicker_frames) os << ", mean flicker " << flicker_sum / double(flicker_frames) << " mean edges";
    if (surface.frames())
      os << ", mean height RMS " << surface.mean_height_rms() << " mean edges, smooth-normal error "
         << surface.mean_smooth_normal_error() << " rad";
    if (surface.transitions())
      os << ", mean SF " << surface.mean_surface_flicker() << " mean edges, ShF "
         << surface.mean_shading_flicker();
    os << "\n";
  }
};

/// Whether `before` and `now` hold the same vertices of a tracked sequence: both have a
/// reference and a result and the same triangles (so vertex i is the same surface point in
/// both; a re-meshed sequence has no flicker by vertex).
bool same_vertices(const FramePositions& before, const FramePositions& now) {
  return !now.result.empty() && before.result.size() == now.result.size() &&
         now.reference.size() == now.result.size() && before.triangles == now.triangles;
}

/// The measures of a --sequence frame with a reference: the result's surface seen from the
/// clean frame (eval/surface_flicker.h), and against the frame before the flicker by vertex
/// (eval/flicker.h), split along the clean normals.
void measure_frame(const FramePositions& before, const FramePositions& now, int threads, FileReport& report,
                   SurfaceFlickerSeries& series) {
  if (now.result.empty()) return;
  const auto n = static_cast<uint32_t>(now.reference.size() / 3);
  const auto m = static_cast<uint32_t>(now.triangles.size() / 3);
  const MeshView clean{now.reference.data(), n, now.triangles.data(), m};
  const MeshView result{now.result.data(), n, now.triangles.data(), m};
  SurfaceSample sample = sample_surface(clean, result, threads);
  if (same_vertices(before, now) && sample.vertices() == n) {
    report.flicker_parts =
        flicker_parts(now.result.data(), before.result.data(), now.reference.data(), before.reference.data(),
                      sample.clean_normal.data(), n, now.reference_mean_edge);
    report.flicker = report.flicker_parts->total;
  } else {
    series.reset();  // other clean vertices: no pair measure against the frame before
  }
  report.surface = series.add(std::move(sample));
}

}  // namespace

int run_folder(const Options& o, Engine& engine) {
  if (!o.output.empty() && !prepare_output_folder(o)) return 2;
  const std::vector<fs::path> files = list_mesh_files(o.input);
  if (files.empty()) {
    std::cerr << "fqfilter: error: no .ply, .obj, .stl or .drc files in '" << o.input << "'\n";
    return 1;
  }
  // --sequence: the files are one stream's frames; the engine keeps its history across them
  // and every frame gets noise of its own (seed + frame index), as a capture would.
  TemporalHistory history;
  if (o.sequence) engine.set_history(&history);
  SequenceSummary summary;
  FramePositions before, now;
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
      Options frame = o;
      if (o.sequence) frame.seed = o.seed + i;
      now = FramePositions{};
      s = run_file_job(files[i].string(), output, frame, engine, report, o.sequence ? &now : nullptr);
    }
    if (!s.ok()) ++failed;
    if (o.sequence && s.ok()) {
      measure_frame(before, now, o.engine.threads, report, summary.surface);
      summary.add(report);
      std::swap(before, now);
    }
    if (!s.ok() || !o.quiet) {
      std::cerr << "[" << (i + 1) << "/" << files.size() << "] " << name << ": ";
      if (s.ok())
        std::cerr << report.vertices << " V, " << std::lround(report.total_ms) << " ms\n";
      else
        std::cerr << "FAILED: " << s.message() << "\n";
    }
    print_report(o, report);
  }
  engine.set_history(nullptr);
  std::cerr << "fqfilter: " << (files.size() - failed) << " of " << files.size() << " files done";
  if (failed) std::cerr << ", " << failed << " failed";
  std::cerr << "\n";
  if (o.sequence) summary.print(std::cerr);
  return failed ? 1 : 0;
}

}  // namespace fq::cli
