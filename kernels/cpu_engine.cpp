#include "kernels/cpu_engine.h"

#include <chrono>
#include <exception>

#include "core/parallel_for.h"
#include "kernels/cpu_stages.h"

namespace fq {

namespace {

// Appends the wall time of each pass to the frame's timings.
class PassClock {
 public:
  PassClock(std::vector<PassTiming>& out, const PassObserver& observer)
      : out_(out), observer_(observer), t0_(Clock::now()) {}
  void lap(const char* name) {
    const auto t = Clock::now();
    out_.push_back({name, std::chrono::duration<double, std::milli>(t - t0_).count()});
    if (observer_) observer_(out_.back());
    t0_ = t;
  }

 private:
  using Clock = std::chrono::steady_clock;
  std::vector<PassTiming>& out_;
  const PassObserver& observer_;
  Clock::time_point t0_;
};

}  // namespace

CpuEngine::CpuEngine(int threads) : threads_(threads_or_all(threads)) {}

Status CpuEngine::run_plan(const MeshView& mesh, const RunPlan& run, FrameResult& out) {
  // The loops of this run skip their remaining chunks once the token expires; the check
  // after the last loop makes such a run an error, never a result.
  // A stopped run may also have failed on its garbage: the cancellation is the cause then.
  CancelScope scope(cancel_);
  const Status s = run_passes(mesh, run, out);
  FQ_RETURN_IF_ERROR(check_cancel());
  return s;
}

void CpuEngine::temporal_step(const MeshView& mesh, const Params& params, FrameResult& out) {
  const size_t passes = out.timings.size();
  Engine::temporal_step(mesh, params, out);
  if (observer_ && out.timings.size() > passes) observer_(out.timings.back());
}

Status CpuEngine::run_passes(const MeshView& mesh, const RunPlan& run, FrameResult& out) {
  PassClock clock(out.timings, observer_);
  // A frame far smaller than the largest one so far gives that one's scratch back.
  if (far_smaller(mesh.num_vertices, f_.points.capacity())) release_scratch();
  FQ_RETURN_IF_ERROR(check_mesh(mesh, threads_));
  FQ_RETURN_IF_ERROR(check_cancel());
  FQ_RETURN_IF_ERROR(compute_normalization(mesh, f_.norm, threads_));
  out.mean_edge = f_.norm.mean_edge;
  clock.lap("normalize");
  FQ_RETURN_IF_ERROR(check_cancel());
  for (PassKind pass : run.passes) {
    if (pass == PassKind::kGrid) {
      cpu::sort_into_grid(mesh, run.grid_cell, f_);
    } else {
      run_pass(pass, run, out);
    }
    // Each pass's time, then the cancel check (a stopped pass leaves garbage that the serial
    // code of the next one must not read).
    clock.lap(pass_name(pass));
    FQ_RETURN_IF_ERROR(check_cancel());
  }
  const uint32_t n = mesh.num_vertices;
  out.positions.resize(3 * size_t(n));
  if (run.params.filter) {
    parallel_for(n, threads_,
                 [&](uint32_t i) { f_.norm.to_input(f_.moved[f_.rank[i]], &out.positions[3 * size_t(i)]); });
  } else {
    std::copy(mesh.positions, mesh.positions + 3 * size_t(n), out.positions.begin());
  }
  clock.lap("output");
  return {};
}

void CpuEngine::run_pass(PassKind pass, const RunPlan& run, FrameResult& out) {
  const ClusterParams& cp = run.params.clustering;
  switch (pass) {
    case PassKind::kGrid:
      break;  // needs the mesh: run_passes
    case PassKind::kBaseQuadrics:
      cpu::base_quadrics(f_, threads_);
      break;
    case PassKind::kNeighbourhoodQuadrics:
      cpu::neighbourhood_quadrics(f_, run.sigma_b, threads_);
      break;
    case PassKind::kDiffusion:
      cpu::diffuse_quadrics(f_, run, threads_);
      break;
    case PassKind::kNoise: {
      const NoiseEstimate e = cpu::estimate_noise(f_, threads_);
      out.keep(e);
      break;
    }
    case PassKind::kRefine: {
      const RefinePlan plan = run.refinement(out.estimate());
      cpu::refine_positions(f_, plan, threads_);
      out.filter_noise = plan.noise;
      break;
    }
    case PassKind::kUpdate:
      cpu::update_positions(f_, run, threads_);
      break;
    case PassKind::kBilateralFilter:
      cpu::bilateral_filter(f_, run, threads_);
      break;
    case PassKind::kScore:
      cpu::cluster_scores(f_, run, threads_);
      break;
    case PassKind::kLink:
      cpu::cluster_links(f_, run, threads_);
      break;
    case PassKind::kModes:
      out.num_clusters = cpu::cluster_labels(f_, out.labels, threads_);
      out.theta = cp.theta;
      break;
    case PassKind::kExportLinks:
      cpu::export_links(f_, cp, out.link_parent, out.link_p, threads_);
      break;
  }
}

}  // namespace fq
