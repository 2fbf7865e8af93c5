// The clustering options that sit on top of an engine's passes, the same code for every
// engine: a target cluster count (theta found per frame from the link forest), clustering on
// the filtered mesh's quadrics (a geometry run and a clustering run on its positions, which
// plan_frame adds to the frame's runs: kernels/frame_plan.h), and connected clusters
// (cluster_connect.h). Engine::process runs the plan's runs, then the step below.
#pragma once

#include "core/mesh_view.h"
#include "core/params.h"
#include "kernels/engine.h"

namespace fq {

/// True when `p` asks for any of the options above.
bool needs_cluster_control(const Params& p);

/// The step after a frame's runs: the plain labels in `out` (with the link forest, for a
/// target count) become those `asked` for; theta the value used (found, with a target) and
/// num_clusters the count achieved. Timed as the pass "cluster_control".
void finish_cluster_control(const MeshView& mesh, const ClusterParams& asked, FrameResult& out);

}  // namespace fq
