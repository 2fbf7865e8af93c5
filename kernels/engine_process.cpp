// Engine::process, how every engine runs a frame: one parameter check, one plan, the plan's
// runs through the engine's run_plan() (the frame's own run followed by the temporal step),
// cluster control on their results and the cancel check. Before, each engine spelled this out
// itself and cluster control called process() back for each extra run, so a frame checked its
// parameters up to six times.
#include <chrono>
#include <string>

#include "core/mesh_checks.h"
#include "core/parallel_for.h"
#include "kernels/cluster_control.h"
#include "kernels/engine.h"

namespace fq {

namespace {

// The outputs a run sets, reset before it so that nothing of the frame before shows through.
// Labels are left to the run (resized and overwritten: a stream of same-sized clustering
// frames does not zero them every time); process() clears them where the run gave none.
void reset_run_outputs(FrameResult& out) {
  out.timings.clear();
  out.num_clusters = 0;
  out.theta = 0.f;
  out.link_parent.clear();
  out.link_p.clear();
  out.keep(NoiseEstimate{});
  out.filter_noise = 0.f;
  out.prior_coverage = 0.f;
  out.prior_share = 0.f;
  out.history_reset = false;
  out.temporal_track = TemporalTrack::kNone;
  out.ids_refused = false;
  out.ids_residual = 0.f;
  out.ids_wide = 0.f;
}

void append_timings(const char* prefix, const FrameResult& from, FrameResult& to) {
  for (const PassTiming& t : from.timings) to.timings.push_back({std::string(prefix) + t.name, t.ms});
}

}  // namespace

int Engine::host_threads() const { return hardware_threads(); }

Status Engine::average_ids(const MeshView& mesh, uint64_t fingerprint, float strength,
                           std::vector<float>& averaged, IdStep& step) {
  step = average_with_ids(mesh, fingerprint, history_->mean_edge, strength, history_->ids, averaged,
                          temporal_scratch_, host_threads());
  return {};
}

Status Engine::process(const MeshView& mesh, const Params& params, FrameResult& out) {
  ++counts_.frames;
  reset_run_outputs(out);
  out.welded_vertices = 0;
  ++counts_.validations;
  Status st = validate(params);
  if (st.ok()) st = run_welded(mesh, plan_frame(params), out);
  // A stopped frame is an error, never a result.
  if (st.ok()) st = check_cancel();
  if (!st.ok() || !params.cluster) out.labels.clear();
  return st;
}

// Seam twins (kernels/seam_weld.h) are filtered as one vertex: the runs, cluster control and the
// temporal step all see the welded frame (a stream's history holds welded results; the next
// frame finds its priors in space, not by index), and the per-vertex outputs go back to the
// input's order and count at the end. A frame without twins pays the search only.
Status Engine::run_welded(const MeshView& mesh, const FramePlan& plan, FrameResult& out) {
  using Clock = std::chrono::steady_clock;
  const auto ms = [](Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); };
  const Clock::time_point t0 = Clock::now();
  const uint32_t twins = weld_seams_ ? seams_.find(mesh, host_threads()) : 0;
  if (twins == 0) return run_frame(mesh, plan, out);
  // The input's check, so that a fault is named in the input's numbering (and the weld reads
  // only indices in range).
  FQ_RETURN_IF_ERROR(check_mesh(mesh, host_threads()));
  const MeshView welded = seams_.weld(mesh, host_threads());
  const double before = ms(Clock::now() - t0);
  FQ_RETURN_IF_ERROR(run_frame(welded, plan, out));
  const Clock::time_point t1 = Clock::now();
  if (plan.params.filter) {
    seams_.spread(out.positions, 3);
  } else {  // the input itself, as without twins (a twin's -0 is not its first copy's +0)
    out.positions.assign(mesh.positions, mesh.positions + 3 * size_t(mesh.num_vertices));
  }
  seams_.spread(out.labels, 1);
  seams_.spread_links(out.link_parent, out.link_p);
  out.welded_vertices = twins;
  out.timings.push_back({"weld", before + ms(Clock::now() - t1)});
  return {};
}

Status Engine::run_once(const MeshView& mesh, const RunPlan& run, FrameResult& out) {
  ++counts_.runs;
  reset_run_outputs(out);
  Status st = run_plan(mesh, run, out);
  if (!st.ok() || !run.params.cluster) out.labels.clear();
  return st;
}

// Track A when the stream keeps its connectivity and its ids follow a smooth motion: the run
// filters the averaged input, alone (its params without the temporal strength, so that no
// engine also takes track B's step), and its result becomes the spatial track's history for
// when the connectivity changes. Otherwise the run on the frame itself, then track B. The
// temporal step comes before a clustering run reads the result: both engines then cluster the
// same positions (the CUDA engine pulls them on the device inside its run, and here its
// history takes them). A stopped frame does not become the stream's history.
Status Engine::run_own(const MeshView& mesh, const RunPlan& run, FrameResult& out) {
  IdStep ids;
  double id_ms = 0.0;
  const bool follows = follows_history(run.params);
  if (follows) {
    const auto start = std::chrono::steady_clock::now();
    FQ_RETURN_IF_ERROR(average_ids(mesh, frame_connectivity(mesh, history_->ids, host_threads()),
                                   run.params.filtering.temporal, id_input_, ids));
    id_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  }
  if (!ids.ran) {
    if (follows) settle_history_normals(*history_, temporal_scratch_, host_threads());
    FQ_RETURN_IF_ERROR(run_once(mesh, run, out));
    FQ_RETURN_IF_ERROR(check_cancel());
    temporal_step(mesh, run.params, out);
  } else {
    MeshView averaged = mesh;
    averaged.positions = id_input_.data();
    RunPlan alone = run;
    alone.params.filtering.temporal = 0.f;
    FQ_RETURN_IF_ERROR(run_once(averaged, alone, out));
    FQ_RETURN_IF_ERROR(check_cancel());
    const auto start = std::chrono::steady_clock::now();
    keep_averaged_result(mesh, out.positions, out.mean_edge, *history_);
    id_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    out.temporal_track = TemporalTrack::kIds;
    out.prior_coverage = 1.f;
    out.prior_share = ids.share;
    out.ids_wide = ids.wide;
  }
  if (follows) {
    out.ids_refused = ids.refused;
    out.ids_residual = ids.residual;
    out.timings.push_back({"temporal_ids", id_ms});
  }
  return {};
}

// The frame's own run writes `out`; the geometry and clustering runs write cluster_runs_
// (kept for the next frame), and the clustering run reads the positions of the run before it.
Status Engine::run_frame(const MeshView& mesh, const FramePlan& plan, FrameResult& out) {
  const FrameResult* shape = &out;
  for (const RunPlan& run : plan.runs) {
    switch (run.role) {
      case RunRole::kFrame:
        FQ_RETURN_IF_ERROR(run_own(mesh, run, out));
        break;
      case RunRole::kGeometry:
        FQ_RETURN_IF_ERROR(run_once(mesh, run, cluster_runs_.geometry));
        shape = &cluster_runs_.geometry;
        if (plan.params.filter) {
          append_timings(run.timing_prefix(), cluster_runs_.geometry, out);
        } else {  // the frame's positions are its input, its passes the geometry's
          out.timings = cluster_runs_.geometry.timings;
          out.mean_edge = cluster_runs_.geometry.mean_edge;
          out.positions.assign(mesh.positions, mesh.positions + 3 * size_t(mesh.num_vertices));
        }
        break;
      case RunRole::kClustering: {
        MeshView filtered = mesh;
        filtered.positions = shape->positions.data();
        FrameResult& c = cluster_runs_.clusters;
        FQ_RETURN_IF_ERROR(run_once(filtered, run, c));
        append_timings(run.timing_prefix(), c, out);
        out.labels.swap(c.labels);
        out.link_parent.swap(c.link_parent);
        out.link_p.swap(c.link_p);
        out.num_clusters = c.num_clusters;
        out.theta = c.theta;
        break;
      }
    }
  }
  if (plan.cluster_control) finish_cluster_control(mesh, plan.params.clustering, out);
  return {};
}

}  // namespace fq
