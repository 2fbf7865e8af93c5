#include "clients/fqfilter/file_job.h"

#include <sys/stat.h>

#include <filesystem>
#include <iostream>
#include <vector>

#include "clients/fqfilter/progress.h"
#include "eval/error_metrics.h"
#include "eval/noise.h"
#include "eval/sharp_edge_recall.h"
#include "eval/surface_distance.h"
#include "eval/vertex_moves.h"
#include "io/mesh_io.h"
#include "io/surface_normals.h"
#include "kernels/cpu_engine.h"
#include "kernels/frame_prep.h"

namespace fq::cli {

namespace {

MeshError measure(const MeshView& reference, const float* positions) {
  return {rmse_over_diagonal(reference, positions),
          distance_to_surface(reference, positions, reference.num_vertices),
          mean_face_normal_error(reference, positions)};
}

/// The clean mesh the metrics compare to: --reference when given, else the input
/// before noise. Leaves `reference_name` empty when there is nothing to compare to.
Status load_reference(const Options& o, const std::string& input, Mesh& clean, std::string& reference_name) {
  reference_name.clear();
  if (!o.reference.empty()) {
    FQ_RETURN_IF_ERROR(io::read_mesh(o.reference, clean));
    reference_name = o.reference;
  } else if (o.noise_sigma > 0) {
    reference_name = input + " (before noise)";
  }
  return {};
}

Status run_engine(const Options& o, Engine& engine, const MeshView& view, FrameResult& result,
                  FileReport& report, Progress& progress) {
  std::vector<std::vector<PassTiming>> runs;
  for (int i = 0; i < o.repeat; ++i) {
    progress.watch(engine, i + 1, o.repeat);
    FQ_RETURN_IF_ERROR(engine.process(view, o.params, result));
    runs.push_back(result.timings);
  }
  summarize_timings(runs, report);
  report.mean_edge = result.mean_edge;
  report.welded_vertices = result.welded_vertices;
  if (o.params.filter && o.params.filtering.method == FilterMethod::kQuadricRefined) {
    report.noise_estimate = result.noise_estimate;
    report.filter_noise = result.filter_noise;
    report.noise_residual = result.noise_residual;
    report.noise_directional = result.noise_directional;
    report.noise_direction = {result.noise_direction.x, result.noise_direction.y, result.noise_direction.z};
    report.noise_alignment = result.noise_alignment;
  }
  if (o.sequence) {  // also at --temporal 0: the per-frame baseline's flicker
    report.prior_coverage = result.prior_coverage;
    report.prior_share = result.prior_share;
    report.history_reset = result.history_reset;
    report.temporal_track = temporal_track_name(result.temporal_track);
    report.ids_refused = result.ids_refused;
    if (result.temporal_track == TemporalTrack::kIds) report.ids_wide = result.ids_wide;
  }
  if (o.params.cluster) {
    report.clusters = result.num_clusters;
    report.theta_used = result.theta;
  }
  return {};
}

void describe(const std::string& input, const Options& o, const Engine& engine, FileReport& r) {
  r = FileReport{};
  r.file = input;
  r.engine = engine.name();
  r.cuda_refused = o.cuda_refused;
  if (const auto* cpu = dynamic_cast<const CpuEngine*>(&engine)) r.threads = cpu->threads();
  r.params = o.params;
  r.noise_sigma = o.noise_sigma;
  r.noise_kind = o.noise_kind;
  r.noise_length = o.noise_length;
  r.seed = o.seed;
  r.repeat = o.repeat;
}

Status fail(FileReport& r, Status s) {
  r.error = s.message();
  return s;
}

void warn(FileReport& r, const std::string& what) {
  r.warnings.push_back(what);
  std::cerr << "fqfilter: warning: '" << r.file << "': " << what << "\n";
}

/// Writes through a temporary file beside the real one, renamed over it once complete, so
/// a failed write never leaves the input half-replaced. Through a symbolic link the
/// link's target is replaced.
Status write_in_place(const std::string& output, const MeshView& mesh, const uint32_t* labels,
                      uint32_t num_clusters, const io::WriteOptions& options,
                      std::vector<std::string>& dropped) {
  namespace fs = std::filesystem;
  const fs::path target = fs::canonical(output);
  fs::path temp = target;
  temp.replace_filename(target.stem().concat(".fq-tmp").concat(target.extension().string()));
  Status s = io::write_mesh(temp.string(), mesh, labels, num_clusters, options, &dropped);
  std::error_code ec;
  if (s.ok()) fs::rename(temp, target, ec);
  if (s.ok() && ec) s = invalid_argument("cannot replace '" + output + "': " + ec.message());
  if (!s.ok()) fs::remove(temp, ec);
  return s;
}

Status write_output(const Options& o, const std::string& output, const MeshView& mesh,
                    const FrameResult& result, io::MeshAttributes& attributes, FileReport& r) {
  if (is_same_file(r.file, output) && !o.in_place)
    return invalid_argument("OUT '" + output + "' is the input file; pass --in-place to replace it");
  MeshView out = mesh;
  out.positions = result.positions.data();
  // Normals of a moved surface must follow it, or the result looks unsmoothed in any viewer.
  if (o.params.filter && !o.keep_normals) {
    io::recompute_normals(out, attributes);
    io::recompute_corner_normals(out, attributes.corner_normal);
  }
  io::WriteOptions options;
  options.drc_position_bits = o.drc_bits;
  options.attributes = &attributes;
  options.colour_clusters = o.colour_clusters;
  const uint32_t* labels = o.params.cluster ? result.labels.data() : nullptr;
  std::vector<std::string> dropped;
  const Status s = o.in_place && is_same_file(r.file, output)
                       ? write_in_place(output, out, labels, result.num_clusters, options, dropped)
                       : io::write_mesh(output, out, labels, result.num_clusters, options, &dropped);
  for (const std::string& d : dropped) warn(r, "not kept in '" + output + "': " + d);
  return s;
}

}  // namespace

Status run_file_job(const std::string& input, const std::string& output, const Options& o, Engine& engine,
                    FileReport& r, FramePositions* kept) {
  describe(input, o, engine, r);
  Progress progress(!o.json && !o.quiet, input);
  progress.show("reading");
  Mesh mesh, clean;
  io::MeshAttributes attributes;
  if (Status s = io::read_mesh(input, mesh, output.empty() ? nullptr : &attributes); !s.ok())
    return fail(r, s);
  for (const std::string& d : attributes.dropped) warn(r, "cannot keep " + d);
  r.vertices = mesh.num_vertices();
  r.triangles = mesh.num_triangles();
  if (Status s = load_reference(o, input, clean, r.reference); !s.ok()) return fail(r, s);
  if (o.noise_sigma > 0) {
    if (o.reference.empty()) clean = mesh;
    add_noise(mesh, o.noise_kind, o.noise_sigma, o.noise_length, o.seed);
  }
  // With --noise 0 the "noisy" input is the input itself: written all the same, so that a
  // sweep over noise levels that starts at 0 finds every file it asked for.
  if (!o.noisy_out.empty()) {
    if (Status s = io::write_mesh(o.noisy_out, mesh.view(), nullptr, 0, 0); !s.ok()) return fail(r, s);
  }
  if (!r.reference.empty()) {
    if (Status s = check_same_connectivity(clean.view(), mesh.view()); !s.ok())
      return fail(
          r, invalid_input("reference '" + o.reference + "' does not match '" + input + "': " + s.message()));
  }
  FrameResult result;
  if (Status s = run_engine(o, engine, mesh.view(), result, r, progress); !s.ok())
    return fail(r, Status(s.code(), "'" + input + "': " + status_code_name(s.code()) + ": " + s.message()));
  if (o.params.filter)
    r.moved =
        vertex_moves(mesh.positions.data(), result.positions.data(), mesh.num_vertices(), result.mean_edge);
  if (!r.reference.empty()) {
    r.input_error = measure(clean.view(), mesh.positions.data());
    if (o.params.filter) r.output_error = measure(clean.view(), result.positions.data());
    if (o.params.cluster) r.sharp_edges = sharp_edge_recall(clean.view(), result.labels.data());
    if (kept && o.params.filter) {
      kept->reference = clean.positions;
      kept->result = result.positions;
      kept->reference_mean_edge = mean_edge_length(clean.view());
      kept->triangles = mesh.triangles;
    }
  }
  if (!output.empty()) {
    progress.show("writing " + output);
    if (Status s = write_output(o, output, mesh.view(), result, attributes, r); !s.ok()) return fail(r, s);
    r.output = output;
  }
  return {};
}

bool is_same_file(const std::string& a, const std::string& b) {
  // stat() follows symbolic links; equal device and inode is the same file, whatever the
  // path (symbolic links, hard links, "./", "..").
  struct stat sa {
  }, sb{};
  return ::stat(a.c_str(), &sa) == 0 && ::stat(b.c_str(), &sb) == 0 && sa.st_dev == sb.st_dev &&
         sa.st_ino == sb.st_ino;
}

}  // namespace fq::cli
