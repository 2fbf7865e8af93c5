#include "python/engine_cache.h"

#include <map>
#include <memory>
#include <mutex>
#include <utility>

namespace fq::py {

namespace {

struct Slot {
  std::mutex busy;
  std::unique_ptr<Engine> engine;
};

Slot& slot_for(const EngineOptions& options) {
  static std::mutex m;
  static std::map<std::pair<int, int>, std::unique_ptr<Slot>> slots;
  const std::lock_guard<std::mutex> lock(m);
  auto& s = slots[{static_cast<int>(options.kind), options.threads}];
  if (!s) s = std::make_unique<Slot>();
  return *s;
}

}  // namespace

Status run_cached_engine(const EngineOptions& options, const MeshView& mesh, const Params& params,
                         FrameResult& out, const std::atomic<bool>* stop, TemporalHistory* history) {
  Slot& slot = slot_for(options);
  const std::lock_guard<std::mutex> lock(slot.busy);
  if (!slot.engine) {
    FQ_ASSIGN_OR_RETURN(slot.engine, make_engine(options));
  }
  const CancelToken token(stop);
  slot.engine->set_cancel_token(&token);
  slot.engine->set_history(history);
  Status s = slot.engine->process(mesh, params, out);
  slot.engine->set_history(nullptr);
  slot.engine->set_cancel_token(nullptr);
  return s;
}

}  // namespace fq::py
