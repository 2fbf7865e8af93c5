#include "kernels/copy_engine.h"

#include <chrono>

#include "kernels/frame_prep.h"

namespace fq {

Status CopyEngine::process(const MeshView& mesh, const Params& params, FrameResult& out) {
  const auto t0 = std::chrono::steady_clock::now();
  FQ_RETURN_IF_ERROR(validate(params));
  FQ_RETURN_IF_ERROR(check_cancel());
  // The positions are copied, as an engine's download would write them.
  out.positions.assign(mesh.positions, mesh.positions + 3 * size_t(mesh.num_vertices));
  out.labels.clear();
  out.link_parent.clear();
  out.link_p.clear();
  out.num_clusters = 0;
  out.theta = 0.f;
  out.mean_edge = 0.0;
  if (params.cluster) {
    out.labels.assign(mesh.num_vertices, 0u);
    out.num_clusters = mesh.num_vertices > 0 ? 1 : 0;
    out.theta = params.clustering.theta;
    out.mean_edge = mean_edge_length(mesh, 1);  // the cell of fqd's id tracking
  }
  out.timings.assign(1, {"copy", std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count()});
  return {};
}

}  // namespace fq
