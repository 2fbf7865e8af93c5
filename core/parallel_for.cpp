#include "core/parallel_for.h"

#include <thread>

namespace fq {

int hardware_threads() {
  const unsigned n = std::thread::hardware_concurrency();
  return n > 0 ? static_cast<int>(n) : 1;
}

}  // namespace fq
