#include "clients/fqfilter/file_job.h"

#include <vector>

#include "kernels/cpu_engine.h"
#include "proto/mesh_io.h"
#include "eval/error_metrics.h"
#include "eval/noise.h"
#include "eval/sharp_edge_recall.h"
#include "eval/surface_distance.h"

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
    if (Status s = io::read_mesh(o.reference, clean); !s.ok()) return s;
    reference_name = o.reference;
  } else if (o.noise_sigma > 0) {
    reference_name = input + " (before noise)";
  }
  return {};
}

Status run_engine(const Options& o, Engine& engine, const MeshView& view, FrameResult& result,
                  FileReport& report) {
  std::vector<std::vector<PassTiming>> runs;
  for (int i = 0; i < o.repeat; ++i) {
    if (Status s = engine.process(view, o.params, result); !s.ok()) return s;
    runs.push_back(result.timings);
  }
  summarize_timings(runs, report);
  report.mean_edge = result.mean_edge;
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
  if (const auto* cpu = dynamic_cast<const CpuEngine*>(&engine)) r.threads = cpu->threads();
  r.params = o.params;
  r.noise_sigma = o.noise_sigma;
  r.seed = o.seed;
  r.repeat = o.repeat;
}

Status fail(FileReport& r, Status s) {
  r.error = s.message();
  return s;
}

}  // namespace

Status run_file_job(const std::string& input, const std::string& output, const Options& o, Engine& engine,
                    FileReport& r) {
  describe(input, o, engine, r);
  Mesh mesh, clean;
  if (Status s = io::read_mesh(input, mesh); !s.ok()) return fail(r, s);
  r.vertices = mesh.num_vertices();
  r.triangles = mesh.num_triangles();
  if (Status s = load_reference(o, input, clean, r.reference); !s.ok()) return fail(r, s);
  if (o.noise_sigma > 0) {
    if (o.reference.empty()) clean = mesh;
    add_gaussian_noise(mesh, o.noise_sigma, o.seed);
  }
  if (!r.reference.empty()) {
    if (Status s = check_same_connectivity(clean.view(), mesh.view()); !s.ok())
      return fail(
          r, invalid_input("reference '" + o.reference + "' does not match '" + input + "': " + s.message()));
  }
  FrameResult result;
  if (Status s = run_engine(o, engine, mesh.view(), result, r); !s.ok())
    return fail(r, Status(s.code(), "'" + input + "': " + status_code_name(s.code()) + ": " + s.message()));
  if (!r.reference.empty()) {
    r.input_error = measure(clean.view(), mesh.positions.data());
    if (o.params.filter) r.output_error = measure(clean.view(), result.positions.data());
    if (o.params.cluster) r.sharp_edges = sharp_edge_recall(clean.view(), result.labels.data());
  }
  if (!output.empty()) {
    MeshView out = mesh.view();
    out.positions = result.positions.data();
    const uint32_t* labels = o.params.cluster ? result.labels.data() : nullptr;
    if (Status s = io::write_mesh(output, out, labels, result.num_clusters, o.drc_bits); !s.ok())
      return fail(r, s);
    r.output = output;
  }
  return {};
}

}  // namespace fq::cli
