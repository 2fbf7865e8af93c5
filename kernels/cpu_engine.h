// The CPU engine: the paper's passes as parallel loops over vertices in grid order,
// calling the same per-vertex math headers as the CUDA engine.
#pragma once

#include <memory>

#include "kernels/cpu_frame.h"
#include "kernels/engine.h"

namespace fq {

class CpuEngine final : public Engine {
 public:
  /// threads <= 0: all hardware threads.
  explicit CpuEngine(int threads = 0);
  std::string name() const override { return "cpu"; }
  int threads() const { return threads_; }

 private:
  Status run_plan(const MeshView& mesh, const RunPlan& run, FrameResult& out) override;
  void temporal_step(const MeshView& mesh, const Params& params, FrameResult& out) override;
  int host_threads() const override { return threads_; }
  void release_scratch() override {
    f_ = CpuFrame{};
    temporal_scratch_ = TemporalScratch{};
  }
  Status run_passes(const MeshView& mesh, const RunPlan& run, FrameResult& out);
  /// One pass of `run` on f_ (the passes before it done); `out` for the passes that write it.
  void run_pass(PassKind pass, const RunPlan& run, FrameResult& out);

  int threads_;
  CpuFrame f_;
};

}  // namespace fq
