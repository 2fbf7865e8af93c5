// Engines for the Python module, made once per (kind, threads) and reused: a CUDA engine
// keeps its device buffers between calls, which is what makes repeated calls fast.
#pragma once

#include <atomic>

#include "kernels/engine.h"

namespace fq::py {

/// Runs `params` on `mesh` with the engine for `options` (made on first use). Calls for the
/// same engine are serialized; call without the GIL. Unavailable engines give a status.
/// Setting `*stop` (may be null) stops the run at the engine's next check (kCancelled);
/// the engine stays usable. `history` (may be null): the stream history of this run (fq.Stream).
Status run_cached_engine(const EngineOptions& options, const MeshView& mesh, const Params& params,
                         FrameResult& out, const std::atomic<bool>* stop = nullptr,
                         TemporalHistory* history = nullptr);

}  // namespace fq::py
