#include "kernels/engine.h"

#include <chrono>
#include <thread>
#include <utility>

#include "common/pair_table.h"
#include "kernels/copy_engine.h"
#include "kernels/cpu_engine.h"
#include "kernels/fq_features.h"

#if FQ_WITH_CUDA
#include "kernels/cuda_engine.h"
#endif

namespace fq {

size_t ClusterRuns::bytes() const {
  size_t n = 0;
  for (const FrameResult* r : {&geometry, &clusters}) {
    n += r->positions.capacity() * sizeof(float) + r->labels.capacity() * sizeof(uint32_t) +
         r->link_parent.capacity() * sizeof(uint32_t) + r->link_p.capacity() * sizeof(float);
  }
  return n;
}

double FrameResult::total_ms() const {
  double t = 0.0;
  for (const PassTiming& p : timings) t += p.ms;
  return t;
}

void FrameResult::keep(const NoiseEstimate& e) {
  noise_estimate = e.noise;
  noise_residual = e.residual;
  noise_directional = e.directional;
  noise_alignment = e.alignment;
  noise_direction = e.direction;
}

NoiseEstimate FrameResult::estimate() const {
  NoiseEstimate e;  // the correlations are not kept: no plan reads them
  e.noise = noise_estimate;
  e.residual = noise_residual;
  e.directional = noise_directional;
  e.alignment = noise_alignment;
  e.direction = noise_direction;
  return e;
}

bool valid_cuda_team(int team) {
  return team == CudaTuning::kTeamBySize || team == 0 || team == 1 || team == 2 || team == 4 || team == 8 ||
         team == 16 || team == 32;
}

namespace {
constexpr std::pair<EngineKind, const char*> kEngineKindNames[] = {{EngineKind::kAuto, "auto"},
                                                                   {EngineKind::kCpu, "cpu"},
                                                                   {EngineKind::kCuda, "cuda"},
                                                                   {EngineKind::kCopy, "copy"}};
}  // namespace

bool parse_engine_kind(const std::string& s, EngineKind& out) {
  const std::optional<EngineKind> k = first_of(kEngineKindNames, s);
  if (k) out = *k;
  return k.has_value();
}

bool Engine::follows_history(const Params& params) const {
  const FilterParams& f = params.filtering;
  return history_ != nullptr && params.filter && f.method == FilterMethod::kQuadricRefined &&
         f.temporal > 0.f;
}

void Engine::report_step(const TemporalStep& step, FrameResult& out) {
  out.prior_coverage = step.coverage;
  out.prior_share = step.share;
  out.history_reset = step.reset;
  out.temporal_track = TemporalTrack::kSpace;
}

const char* temporal_track_name(TemporalTrack track) {
  switch (track) {
    case TemporalTrack::kIds:
      return "ids";
    case TemporalTrack::kSpace:
      return "space";
    case TemporalTrack::kNone:
      break;
  }
  return "none";
}

void Engine::follow_stream_history(const MeshView& mesh, const Params& params, FrameResult& out,
                                   int threads) {
  if (!follows_history(params)) return;
  const auto start = std::chrono::steady_clock::now();
  report_step(follow_history(mesh, out.positions, out.mean_edge, out.noise_estimate,
                             params.filtering.temporal, *history_, temporal_scratch_, threads),
              out);
  out.timings.push_back(
      {"temporal",
       std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count()});
}

const char* engine_kind_name(EngineKind kind) { return second_of(kEngineKindNames, kind).value_or("auto"); }

StatusOr<std::unique_ptr<Engine>> make_engine(const EngineOptions& options, std::string* cuda_refused) {
  if (cuda_refused) cuda_refused->clear();
  if (options.kind == EngineKind::kCpu) return std::make_unique<CpuEngine>(options.threads);
  if (options.kind == EngineKind::kCopy) return std::make_unique<CopyEngine>();
#if FQ_WITH_CUDA
  Status s;
  if (auto e = make_cuda_engine(options.device, &s, options.cuda)) return e;
#else
  const Status s{StatusCode::kUnavailable,
                 "this build of fq has no CUDA support (configure with FQ_CUDA=ON)"};
#endif
  if (options.kind == EngineKind::kCuda) return s;
  // auto: the CPU engine, and the reason kept for whoever asks (a user who expected the GPU).
  if (cuda_refused) *cuda_refused = s.message();
  return std::make_unique<CpuEngine>(options.threads);
}

}  // namespace fq
