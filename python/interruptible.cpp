#include "python/interruptible.h"

#include <pybind11/pybind11.h>

#include <algorithm>
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
  std::future<Status> run = std::async(
      std::launch::async, [&] { return run_cached_engine(options, mesh, params, out, &stop, history); });
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

bool wait_interruptible(const std::function<bool(int ms)>& attempt, double timeout_s) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  for (;;) {
    int slice = int(kSignalPoll.count());
    bool last = false;  // a zero timeout still gets one look
    if (timeout_s >= 0) {
      const double left_ms =
          timeout_s * 1e3 - std::chrono::duration<double, std::milli>(Clock::now() - start).count();
      slice = std::clamp(int(left_ms), 0, slice);
      last = left_ms <= slice;
    }
    bool done = false;
    {
      const pybind11::gil_scoped_release unlocked;
      done = attempt(slice);
    }
    if (done) return true;
    if (PyErr_CheckSignals() != 0) throw pybind11::error_already_set();
    if (last) return false;
  }
}

}  // namespace fq::py
