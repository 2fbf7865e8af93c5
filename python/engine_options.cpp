#include "python/engine_options.h"

#include <pybind11/pybind11.h>

namespace fq::py {

namespace pyb = pybind11;

EngineOptions engine_options(const std::string& engine, int threads) {
  EngineOptions o;
  if (!parse_engine_kind(engine, o.kind))
    throw pyb::value_error("engine must be 'auto', 'cpu' or 'cuda', got '" + engine + "'");
  if (threads < 0) throw pyb::value_error("threads must be >= 0 (0: all hardware threads)");
  o.threads = threads;
  return o;
}

}  // namespace fq::py
