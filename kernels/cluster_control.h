// The clustering options that sit on top of an engine's passes, the same code for every
// engine: a target cluster count (theta found per frame from the link forest), clustering on
// the filtered mesh's quadrics (a second engine run on the filtered positions), and connected
// clusters (cluster_connect.h). An engine's process() hands such frames here first; this
// calls the engine back with plain parameters.
#pragma once

#include "common/status.h"
#include "kernels/engine.h"

namespace fq {

/// True when `p` asks for any of the options above.
bool needs_cluster_control(const Params& p);

/// Processes one frame with `engine` and the options above; `out` as Engine::process gives
/// it, with theta the value used (found, with a target) and num_clusters the count achieved.
Status process_with_cluster_control(Engine& engine, const MeshView& mesh, const Params& p, FrameResult& out);

}  // namespace fq
