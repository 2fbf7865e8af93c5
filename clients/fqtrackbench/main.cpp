// fqtrackbench: label persistence of a stream of synthetic captures of one mesh (each frame
// turned a little further, its own noise, its own vertex order), with the engine's own
// cluster numbering and with tracked ids (kernels/label_tracking.h). Prints a markdown row:
// mesh | frames | noise | degrees per frame | tracking | clustering | mean clusters |
// persistence untracked | tracked (mean) | tracked (worst pair) | sharp-edge recall untracked |
// tracked | tracking ms per frame.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <iostream>

#include "clients/common/tool_app.h"
#include "common/tool_main.h"
#include "core/parallel_for.h"
#include "eval/capture_sequence.h"
#include "eval/label_persistence.h"
#include "eval/sharp_edge_recall.h"
#include "io/mesh_io.h"
#include "kernels/engine.h"
#include "kernels/frame_prep.h"
#include "kernels/label_tracking.h"

namespace {

struct Totals {
  double raw = 0, tracked = 0, min_tracked = 1, clusters = 0, track_ms = 0, recall_raw = 0,
         recall_tracked = 0;
  int pairs = 0, frames = 0;
};

std::string tracking_label(bool ids_only, int rings, int vote_frames) {
  if (ids_only) return "ids only";
  std::string s = "ids";
  if (rings > 0) s += " + borders " + std::to_string(rings) + " rings";
  if (vote_frames > 1) s += " + vote " + std::to_string(vote_frames) + " frames";
  return s;
}

int run(int argc, char** argv) {
  fq::TrackingOptions defaults;
  int to_rings = defaults.sticky_rings, vote_frames = defaults.vote_frames;
  fq::client::ToolApp app{"fqtrackbench: cluster id persistence over synthetic capture frames",
                          "fqtrackbench"};
  std::string mesh_path;
  int frames = 10, threads = 0;
  double noise = 0.2, degrees = 0.0;
  fq::Params p;
  p.filter = false;
  p.cluster = true;
  app.add_option("MESH", mesh_path, "Clean mesh")->required();
  app.add_option("--frames", frames, "Frames in the stream")->check(CLI::Range(2, 100000));
  app.add_option("--noise", noise, "Noise per frame, mean edges")->check(CLI::Range(0.0, 10.0));
  app.add_option("--degrees", degrees, "Turn per frame about the vertical axis");
  app.add_option("--target-clusters", p.clustering.target_clusters, "0: theta");
  app.add_option("--theta", p.clustering.theta);
  app.add_option("--sigma-d", p.clustering.sigma_d);
  app.add_option("--sigma-q", p.clustering.sigma_q);
  app.add_option("--threads", threads, "CPU engine threads (0 = all)");
  app.add_option("--min-cluster-size", p.clustering.min_cluster_size);
  bool ids_only = false;
  app.add_option("--sticky-rings", to_rings, "Rings a border may move back");
  app.add_option("--vote-frames", vote_frames, "Frames of the per-vertex majority vote (1 = off)")
      ->check(CLI::Range(1, 64));
  app.add_flag("--ids-only", ids_only, "Match ids only (no sticky boundaries, no vote)");
  CLI11_PARSE(app, argc, argv);
  fq::Mesh clean;
  if (fq::Status s = fq::io::read_mesh(mesh_path, clean); !s.ok()) {
    std::cerr << "fqtrackbench: error: " << s.message() << "\n";
    return 1;
  }
  fq::EngineOptions eo;
  eo.kind = fq::EngineKind::kCpu;
  eo.threads = threads;
  fq::StatusOr<std::unique_ptr<fq::Engine>> made = fq::make_engine(eo);
  if (!made.ok()) {
    std::cerr << "fqtrackbench: error: " << made.status().message() << "\n";
    return 1;
  }
  const std::unique_ptr<fq::Engine> engine = std::move(made).value();
  const float cell = float(fq::mean_edge_length(clean.view()));
  fq::TrackingOptions to;
  to.cell = cell;
  to.max_distance = 8 * cell;
  to.threads = fq::threads_or_all(threads);
  to.sticky_rings = to_rings;
  to.vote_frames = ids_only ? 1 : vote_frames;
  fq::LabelTracker tracker;
  fq::Mesh prev;
  std::vector<uint32_t> prev_raw, prev_ids;
  Totals t;
  for (int f = 0; f < frames; ++f) {
    const fq::Mesh m = fq::capture_frame(clean, f * degrees, noise, 1000 + f);
    fq::FrameResult r;
    if (fq::Status s = engine->process(m.view(), p, r); !s.ok()) {
      std::cerr << "fqtrackbench: error: " << s.message() << "\n";
      return 1;
    }
    std::vector<uint32_t> ids = r.labels;
    const auto t0 = std::chrono::steady_clock::now();
    if (!ids_only) {
      to.triangles = m.triangles.data();
      to.num_triangles = m.num_triangles();
    }
    tracker.track(m.positions.data(), m.num_vertices(), ids, r.num_clusters, to);
    t.track_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    t.clusters += r.num_clusters;
    const fq::Mesh truth =
        fq::capture_frame(clean, f * degrees, 0.0, 1000 + f);  // same vertex order, no noise
    t.recall_raw += fq::sharp_edge_recall(truth.view(), r.labels.data()).recall;
    t.recall_tracked += fq::sharp_edge_recall(truth.view(), ids.data()).recall;
    ++t.frames;
    if (f > 0) {
      const uint32_t n = m.num_vertices(), pn = prev.num_vertices();
      t.raw += fq::label_persistence(prev.positions.data(), prev_raw.data(), pn, m.positions.data(),
                                     r.labels.data(), n, cell);
      const double k = fq::label_persistence(prev.positions.data(), prev_ids.data(), pn, m.positions.data(),
                                             ids.data(), n, cell);
      t.tracked += k;
      t.min_tracked = std::min(t.min_tracked, k);
      ++t.pairs;
    }
    prev = m;
    prev_raw = r.labels;
    prev_ids = ids;
  }
  std::printf("| %s | %d | %g | %g | %s | %s | %.1f | %.3f | %.3f | %.3f | %.3f | %.3f | %.1f |\n",
              mesh_path.c_str(), frames, noise, degrees,
              tracking_label(ids_only, to_rings, to.vote_frames).c_str(),
              p.clustering.target_clusters ? ("K " + std::to_string(p.clustering.target_clusters)).c_str()
                                           : ("θ " + std::to_string(p.clustering.theta)).c_str(),
              t.clusters / t.frames, t.raw / t.pairs, t.tracked / t.pairs, t.min_tracked,
              t.recall_raw / t.frames, t.recall_tracked / t.frames, t.track_ms / t.frames);
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return fq::tool_main("fqtrackbench", run, argc, argv); }
