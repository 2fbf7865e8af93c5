#include "kernels/engine.h"

#include <chrono>

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

bool valid_cuda_team(int team) {
  return team == CudaTuning::kTeamBySize || team == 0 || team == 1 || team == 2 || team == 4 || team == 8 ||
         team == 16 || team == 32;
}

bool parse_engine_kind(const std::string& s, EngineKind& out) {
  if (s == "auto") out = EngineKind::kAuto;
  else if (s == "cpu") out = EngineKind::kCpu;
  else if (s == "cuda") out = EngineKind::kCuda;
  else return false;
  return true;
}

void Engine::follow_stream_history(const MeshView& mesh, const Params& params, FrameResult& out, int threads) {
  const FilterParams& f = params.filtering;
  if (history_ == nullptr || !params.filter || f.method != FilterMethod::kQuadricRefined || !(f.temporal > 0.f))
    return;
  const auto start = std::chrono::steady_clock::now();
  const TemporalStep step = follow_history(mesh, out.positions, out.mean_edge, out.noise_estimate, f.temporal,
                                           *history_, temporal_scratch_, threads);
  out.prior_coverage = step.coverage;
  out.prior_share = step.share;
  out.history_reset = step.reset;
  out.timings.push_back(
      {"temporal", std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count()});
}

StatusOr<std::unique_ptr<Engine>> make_engine(const EngineOptions& options) {
  if (options.kind == EngineKind::kCpu) return std::make_unique<CpuEngine>(options.threads);
#if FQ_WITH_CUDA
  Status s;
  if (auto e = make_cuda_engine(options.device, &s, options.cuda)) return e;
  if (options.kind == EngineKind::kCuda) return s;
#else
  if (options.kind == EngineKind::kCuda)
    return Status{StatusCode::kUnavailable,
                  "this build of fq has no CUDA support (configure with FQ_CUDA=ON)"};
#endif
  return std::make_unique<CpuEngine>(options.threads);
}

}  // namespace fq
