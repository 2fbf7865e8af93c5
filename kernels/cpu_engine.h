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
  Status process(const MeshView& mesh, const Params& params, FrameResult& out) override;
  int threads() const { return threads_; }

 private:
  void release_scratch() override {
    f_ = CpuFrame{};
    temporal_scratch_ = TemporalScratch{};
  }
  Status run(const MeshView& mesh, const Params& params, FrameResult& out);

  int threads_;
  CpuFrame f_;
};

}  // namespace fq
