// Placeholder until the CUDA engine lands (issue: GPU engine): reports it unavailable so
// that `auto` falls back to the CPU engine.
#include "cuda_engine.h"

namespace fq {

std::unique_ptr<Engine> make_cuda_engine(int, Status* why) {
  if (why) *why = {StatusCode::kUnavailable, "the CUDA engine is not implemented in this build yet"};
  return nullptr;
}

}  // namespace fq
