#include "kernels/copy_engine.h"

#include <chrono>

#include "kernels/frame_prep.h"

namespace fq {

Status CopyEngine::run_plan(const MeshView& mesh, const RunPlan& run, FrameResult& out) {
  const auto t0 = std::chrono::steady_clock::now();
  FQ_RETURN_IF_ERROR(check_cancel());
  // The positions are copied, as an engine's download would write them.
  out.positions.assign(mesh.positions, mesh.positions + 3 * size_t(mesh.num_vertices));
  out.mean_edge = 0.0;
  const Params& params = run.params;
  if (params.cluster) {
    out.labels.assign(mesh.num_vertices, 0u);
    out.num_clusters = mesh.num_vertices > 0 ? 1 : 0;
    out.theta = params.clustering.theta;
    out.mean_edge = mean_edge_length(mesh, 1);  // the cell of fqd's id tracking
    if (params.clustering.keep_links) {         // one tree: every vertex links to vertex 0, fully
      out.link_parent.assign(mesh.num_vertices, 0u);
      out.link_p.assign(mesh.num_vertices, 1.f);
    }
  }
  out.timings.assign(
      1, {"copy", std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count()});
  return {};
}

}  // namespace fq
