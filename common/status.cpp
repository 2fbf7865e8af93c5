#include "common/status.h"

#include <cstddef>
#include <iterator>

namespace fq {

const char* status_code_name(StatusCode code) {
  // In the enum's order.
  static constexpr const char* kNames[] = {
      "ok", "invalid argument", "invalid input", "unavailable", "internal error", "i/o error", "cancelled"};
  static_assert(std::size(kNames) == static_cast<size_t>(StatusCode::kCancelled) + 1, "one name per code");
  const auto i = static_cast<size_t>(code);
  return i < std::size(kNames) ? kNames[i] : "unknown";
}

}  // namespace fq
