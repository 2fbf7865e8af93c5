// The engine interface: one frame in, filtered positions and/or cluster labels out.
// Implementations: the CPU engine (threads) and the CUDA engine (persistent device buffers).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "common/status.h"
#include "common/status_or.h"
#include "core/cancel_token.h"
#include "core/mesh_view.h"
#include "core/params.h"
#include "kernels/frame_plan.h"
#include "kernels/seam_weld.h"
#include "kernels/temporal.h"

namespace fq {

struct PassTiming {
  std::string name;
  double ms = 0.0;
};

/// Output of one frame. Buffers are reused (grow-only) when the same object is passed again.
enum class TemporalTrack : uint8_t { kNone, kIds, kSpace };

/// "none", "ids" or "space".
const char* temporal_track_name(TemporalTrack track);

struct FrameResult {
  std::vector<float> positions;  ///< 3 per vertex, input order; the input when !filter
  std::vector<uint32_t> labels;  ///< one per vertex in 0..num_clusters-1; empty when !cluster
  uint32_t num_clusters = 0;
  float theta = 0.f;  ///< theta that gave the labels (found per frame with a target)
  /// With ClusterParams::keep_links, per vertex (input order): the vertex it links to
  /// before the theta cut (itself for a root at any theta) and that link's proximity p;
  /// the labels at theta are those of the links with p >= 1 - theta.
  std::vector<uint32_t> link_parent;
  std::vector<float> link_p;
  double mean_edge = 0.0;  ///< the unit of every sigma, in input units
  /// "qf+": the noise estimated from the frame (kernels/noise_estimate.h) and the noise the
  /// filter's strengths came from (the estimate × strength, or the noise given), both in mean
  /// edge lengths; 0 for the other methods.
  float noise_estimate = 0.f;
  float filter_noise = 0.f;
  /// "qf+": the residual of the estimate's fits (noise and the detail a quadratic over two
  /// rings cannot follow, mean edge lengths): noise_estimate is the share of it read as
  /// noise, the rest was read as the surface's detail.
  float noise_residual = 0.f;
  /// "qf+": the estimate's directional part (kernels/noise_estimate.h, NoiseEstimate): the noise
  /// along one direction shared by the frame (a range scan's line of sight; mean edge lengths, 0
  /// where none stands out), that unit direction in the input's coordinates (zero without a
  /// usable sample), and the RMS of n·d over the samples (how much of it lies along the normals).
  float noise_directional = 0.f;
  float noise_alignment = 0.f;
  Vec3 noise_direction{0.f, 0.f, 0.f};
  /// Temporal filtering: the share of vertices that found a prior in the stream's last result,
  /// the mean pull towards it, and whether this frame reset the history (a scene cut).
  float prior_coverage = 0.f;
  float prior_share = 0.f;
  bool history_reset = false;
  /// Which temporal track ran (docs/ALGORITHM.md, "Temporal filtering"): ids (track A: the
  /// input averaged through the vertex ids, kernels/temporal_ids.h), space (track B: the result
  /// pulled towards the last one, kernels/temporal.h), or none (no history asked for).
  TemporalTrack temporal_track = TemporalTrack::kNone;
  /// Track A: the frame shared the last frame's connectivity but its ids did not follow a
  /// smooth motion (it fell back to track B); the typical RMS of the displacement the motion
  /// left (mean edges; 0 when track A did not look).
  bool ids_refused = false;
  float ids_residual = 0.f;
  /// Track A: the mean share of the motion's wide estimate (kernels/temporal_math.h,
  /// wide_share): near 1 where the motion is smooth over eight rings, low where it bends.
  float ids_wide = 0.f;
  /// Vertices at the exact position of an earlier one (seam twins, kernels/seam_weld.h) that
  /// the frame was filtered without: each is given its first copy's result. 0: none.
  uint32_t welded_vertices = 0;
  std::vector<PassTiming> timings;

  double total_ms() const;
  /// "qf+": the estimate kept in the fields above (keep), and as the refinement reads it (estimate).
  void keep(const NoiseEstimate& e);
  NoiseEstimate estimate() const;
};

/// Buffers of the extra engine runs that cluster control makes (kernels/cluster_control.h): the
/// clustering geometry and the clustering pass on it. Kept by the engine for its next frame,
/// like its own scratch, and given back by Engine::release_memory().
struct ClusterRuns {
  FrameResult geometry, clusters;

  /// Bytes their buffers hold.
  size_t bytes() const;
};

/// Told about each pass as it ends (progress displays).
using PassObserver = std::function<void(const PassTiming&)>;

/// How a frame runs, the same for every engine (a template method): process() checks the
/// parameters once, welds coincident vertices into one (kernels/seam_weld.h; the outputs go
/// back to the input's order and count), resolves the frame's plan (kernels/frame_plan.h), runs
/// each of the plan's engine runs through the engine's run_plan(), composes cluster control from
/// those runs (kernels/cluster_control.h), checks the cancel token, and ends with the temporal step.
/// Engines implement only run_plan(): one run's passes on their hardware.
class Engine {
 public:
  virtual ~Engine() = default;
  /// The CPU engine calls `observer` after each pass, on the thread running process(); the
  /// CUDA engine times its passes on the device and does not call it. Empty: none.
  void set_pass_observer(PassObserver observer) { observer_ = std::move(observer); }
  /// process() checks `token` between passes (the CPU engine also between chunks of its
  /// loops) and returns kCancelled once it has expired. It must outlive the runs that use
  /// it; null: none. Frames that finish are computed exactly as without a token.
  void set_cancel_token(const CancelToken* token) { cancel_ = token; }
  /// The stream history "qf+" filters the next frames with when FilterParams::temporal > 0
  /// (kernels/temporal.h): read and updated by process(); null: every frame alone. Like the
  /// token, it must outlive the runs that use it; a stream's frames must come in order.
  void set_history(TemporalHistory* history) { history_ = history; }
  /// Whether process() filters coincident vertices as one (kernels/seam_weld.h); on by
  /// default. Off, each copy is filtered alone and a seam may crack; a frame without twins
  /// gives the same result either way, and off spares it the search (about 10 ms a million
  /// vertices on one core).
  void set_weld_seams(bool on) { weld_seams_ = on; }
  /// "cpu" or "cuda:<device name>".
  virtual std::string name() const = 0;
  /// Processes one frame. Bad parameters or a bad mesh give a non-ok status and leave the
  /// engine usable for the next frame, as does a run stopped by the cancel token.
  Status process(const MeshView& mesh, const Params& params, FrameResult& out);
  /// Gives back the buffers kept for the next frame (an idle engine: fqd calls it after
  /// caps.pool_idle_s without frames): the engine's own scratch and cluster control's runs;
  /// the next frame allocates them again.
  void release_memory() {
    cluster_runs_ = {};
    seams_.release();
    release_scratch();
  }
  /// The extra runs' buffers kept for the next frame (what release_memory() gives back besides
  /// the engine's own scratch).
  const ClusterRuns& cluster_runs() const { return cluster_runs_; }

  /// What this engine has done so far: frames (process() calls), parameter checks and engine
  /// runs (run_plan() calls; a frame clustered on its filtered mesh makes up to three).
  struct Counts {
    uint64_t frames = 0, validations = 0, runs = 0;
  };
  const Counts& counts() const { return counts_; }

 protected:
  /// One run of the frame's plan: its passes on `mesh` into `out`, whose scalar outputs and
  /// timings process() has reset (labels are left for the run to overwrite; process() clears
  /// them after a failed run or one without clustering). Ok, kCancelled or the first error.
  virtual Status run_plan(const MeshView& mesh, const RunPlan& run, FrameResult& out) = 0;
  /// The temporal step on the frame's own run's result, before any clustering run reads it
  /// (kernels/temporal.h): by default follow_stream_history on the host with host_threads().
  virtual void temporal_step(const MeshView& mesh, const Params& params, FrameResult& out) {
    follow_stream_history(mesh, params, out, host_threads());
  }
  /// Track A's step (kernels/temporal_ids.h) of the stream's history on `mesh`, its averaged
  /// input into `averaged`: by default average_with_ids on the host with host_threads(); the
  /// CUDA engine runs its per-vertex math on the device. Ok, or the device's error.
  virtual Status average_ids(const MeshView& mesh, uint64_t fingerprint, float strength,
                             std::vector<float>& averaged, IdStep& step);
  /// Host threads of the steps process() runs on the host.
  virtual int host_threads() const;
  /// The engine's own scratch (host or device), given back by release_memory() and when a
  /// frame is far smaller than the largest so far (far_smaller). Not cluster_runs(): a frame
  /// may be one of those runs.
  virtual void release_scratch() {}
  /// Ok, or kCancelled once the cancel token has expired.
  Status check_cancel() const { return cancel_ != nullptr ? cancel_->check() : Status{}; }
  /// Whether a frame of `vertices` should first give back scratch sized for `capacity`
  /// vertices: it is far smaller than the largest frame so far (both engines' rule).
  static bool far_smaller(uint32_t vertices, size_t capacity) {
    return size_t(vertices) * 4 < capacity && capacity > (size_t(1) << 16);
  }

  /// The temporal step (kernels/temporal.h) of a "qf+" result in `out` (input order), when a
  /// history is set and params ask for it; timed as the pass "temporal" in out.timings.
  void follow_stream_history(const MeshView& mesh, const Params& params, FrameResult& out, int threads);
  /// Whether this frame takes the temporal step: a history is set and params ask for it.
  bool follows_history(const Params& params) const;
  /// The step's report in `out`.
  static void report_step(const TemporalStep& step, FrameResult& out);

  PassObserver observer_;
  const CancelToken* cancel_ = nullptr;
  TemporalHistory* history_ = nullptr;
  TemporalScratch temporal_scratch_;  ///< the engine's scratch: release_scratch() gives it back

 private:
  Status run_welded(const MeshView& mesh, const FramePlan& plan, FrameResult& out);
  Status run_frame(const MeshView& mesh, const FramePlan& plan, FrameResult& out);
  Status run_once(const MeshView& mesh, const RunPlan& run, FrameResult& out);
  /// The frame's own run with the stream's temporal step around it: track A averages the input
  /// before the run when the ids allow (kernels/temporal_ids.h), else track B pulls the result
  /// after it (temporal_step).
  Status run_own(const MeshView& mesh, const RunPlan& run, FrameResult& out);

  std::vector<float> id_input_;  ///< track A's averaged input of the frame
  ClusterRuns cluster_runs_;
  SeamWeld seams_;
  bool weld_seams_ = true;
  Counts counts_;
};

/// kCopy: the copy engine (copy_engine.h), which returns its input, for measuring the host
/// path around an engine.
enum class EngineKind { kAuto, kCpu, kCuda, kCopy };

/// Kernel choices of the CUDA engine (docs/BENCHMARKS.md has the measurements behind the
/// defaults). Fixed for an engine's lifetime.
struct CudaTuning {
  /// Lanes per vertex in the neighbourhood passes: kTeamBySize picks 8, 4 or 1 from the
  /// vertices per SM; 0 runs the one-thread-per-vertex kernels that call the math headers
  /// directly; 1, 2, 4, 8, 16 or 32 a fixed team.
  static constexpr int kTeamBySize = -1;
  int team = kTeamBySize;
  /// Gaussian weights of the team kernels through the hardware __expf instead of the
  /// accurate exp of gaussian.h (3-5 % faster, last bits differ).
  bool fast_exp = false;
};

struct EngineOptions {
  EngineKind kind = EngineKind::kAuto;
  int threads = 0;  ///< CPU threads; 0 = all hardware threads
  int device = 0;   ///< CUDA device ordinal
  CudaTuning cuda;
};

/// True for the team values CudaTuning accepts.
bool valid_cuda_team(int team);

/// Parses "auto" | "cpu" | "cuda" | "copy".
bool parse_engine_kind(const std::string& s, EngineKind& out);
/// "auto", "cpu", "cuda" or "copy".
const char* engine_kind_name(EngineKind kind);

/// CUDA when asked for or (auto) when a device is present, the CPU engine otherwise.
/// kUnavailable (with the reason) when an explicitly requested engine is not present.
/// `cuda_refused` (may be null): where auto fell back to the CPU, why CUDA was not used ("this
/// build has no CUDA support", "no CUDA device is present", a driver error...); cleared otherwise.
StatusOr<std::unique_ptr<Engine>> make_engine(const EngineOptions& options,
                                              std::string* cuda_refused = nullptr);

}  // namespace fq
