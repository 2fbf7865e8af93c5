#include "kernels/cpu_engine.h"

#include <chrono>
#include <exception>

#include "kernels/cluster_control.h"
#include "kernels/cpu_stages.h"
#include "core/parallel_for.h"

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

Status CpuEngine::process(const MeshView& mesh, const Params& params, FrameResult& out) {
  // The loops of this run skip their remaining chunks once the token expires; the check
  // after the last loop makes such a run an error, never a result.
  // A stopped run may also have failed on its garbage: the cancellation is the cause then.
  CancelScope scope(cancel_);
  const Status s = run(mesh, params, out);
  FQ_RETURN_IF_ERROR(check_cancel());
  return s;
}

Status CpuEngine::run(const MeshView& mesh, const Params& params, FrameResult& out) {
  out.timings.clear();
  out.labels.clear();
  out.num_clusters = 0;
  out.theta = 0.f;
  out.link_parent.clear();
  out.link_p.clear();
  out.noise_estimate = 0.f;
  out.filter_noise = 0.f;
  out.prior_coverage = 0.f;
  out.prior_share = 0.f;
  out.history_reset = false;
  FQ_RETURN_IF_ERROR(validate(params));
  if (needs_cluster_control(params)) return process_with_cluster_control(*this, mesh, params, out);
  PassClock clock(out.timings, observer_);
  // Ends a pass: its time, then the cancel check (a stopped pass leaves garbage that the
  // serial code of the next one must not read).
  auto pass_done = [&](const char* name) {
    clock.lap(name);
    return check_cancel();
  };
  // A frame far smaller than the largest one so far gives that one's scratch back.
  if (far_smaller(mesh.num_vertices, f_.points.capacity())) release_scratch();
  FQ_RETURN_IF_ERROR(check_mesh(mesh, threads_));
  FQ_RETURN_IF_ERROR(check_cancel());
  FQ_RETURN_IF_ERROR(compute_normalization(mesh, f_.norm, threads_));
  out.mean_edge = f_.norm.mean_edge;
  FQ_RETURN_IF_ERROR(pass_done("normalize"));
  const FilterParams& fp = params.filtering;
  const bool need_quadrics = params.cluster || fp.uses_quadrics();

  cpu::sort_into_grid(mesh, fp.sigma_s, f_);
  FQ_RETURN_IF_ERROR(pass_done("grid"));
  cpu::base_quadrics(f_, threads_);
  FQ_RETURN_IF_ERROR(pass_done("base_quadrics"));
  if (need_quadrics) {
    cpu::neighbourhood_quadrics(f_, fp.effective_sigma_b(), threads_);
    FQ_RETURN_IF_ERROR(pass_done("neighbourhood_quadrics"));
    cpu::diffuse_quadrics(f_, fp, threads_);
    FQ_RETURN_IF_ERROR(pass_done("diffusion"));
  }
  if (params.filter) {
    if (fp.method == FilterMethod::kQuadricRefined) {
      const NoiseEstimate noise = cpu::estimate_noise(f_, threads_);
      FQ_RETURN_IF_ERROR(pass_done("noise"));
      const RefinePlan plan = plan_refinement(fp.refine, noise.noise);
      cpu::refine_positions(f_, plan, threads_);
      out.noise_estimate = noise.noise;
      out.filter_noise = plan.noise;
      FQ_RETURN_IF_ERROR(pass_done("refine"));
    } else if (fp.uses_quadrics()) {
      cpu::update_positions(f_, fp, threads_);
      FQ_RETURN_IF_ERROR(pass_done("update"));
    } else {
      cpu::bilateral_filter(f_, fp, threads_);
      FQ_RETURN_IF_ERROR(pass_done("bilateral_filter"));
    }
  }
  if (params.cluster) {
    cpu::cluster_scores(f_, params.clustering, threads_);
    FQ_RETURN_IF_ERROR(pass_done("score"));
    cpu::cluster_links(f_, params.clustering, threads_);
    FQ_RETURN_IF_ERROR(pass_done("link"));
    out.num_clusters = cpu::cluster_labels(f_, out.labels, threads_);
    out.theta = params.clustering.theta;
    FQ_RETURN_IF_ERROR(pass_done("modes"));
    if (params.clustering.keep_links) {
      cpu::export_links(f_, params.clustering, out.link_parent, out.link_p, threads_);
      FQ_RETURN_IF_ERROR(pass_done("export_links"));
    }
  }
  const uint32_t n = mesh.num_vertices;
  out.positions.resize(3 * size_t(n));
  if (params.filter) {
    parallel_for(n, threads_, [&](uint32_t i) { f_.norm.to_input(f_.moved[f_.rank[i]], &out.positions[3 * size_t(i)]); });
  } else {
    std::copy(mesh.positions, mesh.positions + 3 * size_t(n), out.positions.begin());
  }
  clock.lap("output");
  FQ_RETURN_IF_ERROR(check_cancel());  // a stopped frame must not become the stream's history
  const size_t passes = out.timings.size();
  follow_stream_history(mesh, params, out, threads_);
  if (observer_ && out.timings.size() > passes) observer_(out.timings.back());
  return {};
}

}  // namespace fq
