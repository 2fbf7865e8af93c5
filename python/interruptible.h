// Engine runs that Ctrl-C stops. Python runs its signal handlers on the main thread between
// bytecodes, so an engine run on the calling thread without the GIL would make Ctrl-C wait
// for the whole run (8.5 s on the dragon). The engine runs on a worker thread instead; the
// calling thread waits for it in short slices and, between them, takes the GIL and lets
// Python handle pending signals.
#pragma once

#include <functional>

#include "kernels/engine.h"

namespace fq::py {

/// Runs `params` on `mesh` with the cached engine for `options`; call with the GIL held. A
/// signal handler that raises while the engine runs (KeyboardInterrupt on Ctrl-C) stops the
/// engine through its cancel token, and the exception propagates once the engine has
/// returned (pybind11::error_already_set). Otherwise: the engine's status. `history` (may be
/// null): the stream history of the run (fq.Stream).
Status run_interruptible(const EngineOptions& options, const MeshView& mesh, const Params& params,
                         FrameResult& out, TemporalHistory* history = nullptr);

/// Socket waits that Ctrl-C stops, for fq.Producer and fq.Consumer: calls `attempt(ms)` (which
/// may block up to ms milliseconds) with the GIL released until it returns true or `timeout_s`
/// seconds have passed (negative: no limit), handling pending signals with the GIL held
/// between calls. Whether an attempt succeeded; a handler's exception propagates
/// (pybind11::error_already_set). Call with the GIL held.
bool wait_interruptible(const std::function<bool(int ms)>& attempt, double timeout_s);

}  // namespace fq::py
