// Counters by reason for things fqd refuses: one atomic per enumerator of `Reason` (which
// ends with kCount), never one per peer or per name, so that junk cannot grow them.
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>

namespace fq::daemon {

template <class Reason>
class ReasonCounters {
 public:
  static constexpr size_t kReasons = static_cast<size_t>(Reason::kCount);

  void add(Reason r) { counts_[static_cast<size_t>(r)].fetch_add(1, std::memory_order_relaxed); }
  uint64_t get(Reason r) const { return counts_[static_cast<size_t>(r)].load(std::memory_order_relaxed); }

 private:
  std::array<std::atomic<uint64_t>, kReasons> counts_{};
};

}  // namespace fq::daemon
