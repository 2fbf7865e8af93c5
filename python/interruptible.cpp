#include "python/interruptible.h"

#include <pybind11/pybind11.h>

#include <atomic>
#include <chrono>
#include <future>

#include "python/engine_cache.h"

namespace fq::py {

namespace {

// Time between two looks at pending signals: Ctrl-C is answered within about this much
// plus the engine's time to its next cancel check. A finished run is seen at once (the
// wait ends when the result is ready), so short calls pay nothing for it.
constexpr std::chrono::milliseconds kSignalPoll{50};

}  // namespace

Status run_interruptible(const EngineOptions& options, const MeshView& mesh, const Params& params,
                         FrameResult& out, TemporalHistory* history) {
  std::atomic<bool> stop{false};
  std::future<Status> run = std::async(std::launch::async, [&] {
    return run_cached_engine(options, mesh, params, out, &stop, history);
  });
  for (;;) {
    {
      const pybind11::gil_scoped_release unlocked;
      if (run.wait_for(kSignalPoll) == std::future_status::ready) break;
    }
    if (PyErr_CheckSignals() != 0) {  // a handler raised: its exception is now set
      stop = true;
      {
        const pybind11::gil_scoped_release unlocked;
        run.wait();
      }
      throw pybind11::error_already_set();
    }
  }
  return run.get();
}

}  // namespace fq::py
