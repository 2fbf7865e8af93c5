// Engines for the Python module, made once per (kind, threads) and reused: a CUDA engine
// keeps its device buffers between calls, which is what makes repeated calls fast.
#pragma once

#include "kernels/engine.h"

namespace fq::py {

/// Runs `params` on `mesh` with the engine for `options` (made on first use). Calls for the
/// same engine are serialized; call without the GIL. Unavailable engines give a status.
Status run_cached_engine(const EngineOptions& options, const MeshView& mesh, const Params& params,
                         FrameResult& out, std::string* engine_name = nullptr);

}  // namespace fq::py
