// The copy engine: a frame's result is its input (positions as they came, every vertex in
// cluster 0 and the mean edge when clustering is asked for). It stands in for an engine that costs the host
// nothing, so that fqd's own host path (ingest, decode, checks, tracking, encode, publish)
// can be measured and profiled at full load on a machine without a GPU (docs/BENCHMARKS.md).
// Not a filter: its results are not filtered, and it has no temporal step.
#pragma once

#include "kernels/engine.h"

namespace fq {

class CopyEngine final : public Engine {
 public:
  std::string name() const override { return "copy"; }

 private:
  Status run_plan(const MeshView& mesh, const RunPlan& run, FrameResult& out) override;
  void temporal_step(const MeshView&, const Params&, FrameResult&) override {}
};

}  // namespace fq
