// Factory of the CUDA engine. CUDA-free on purpose: device state stays behind the Engine.
#pragma once

#include <memory>

#include "engine.h"

namespace fq {

/// The CUDA engine on device `device`, or null with a reason (no device, driver too old...).
std::unique_ptr<Engine> make_cuda_engine(int device, Status* why);

}  // namespace fq
