// The engine= and threads= arguments of every engine call, checked.
#pragma once

#include <string>

#include "kernels/engine.h"

namespace fq::py {

/// EngineOptions from Python's engine= and threads=; ValueError for a bad name or count.
EngineOptions engine_options(const std::string& engine, int threads);

}  // namespace fq::py
