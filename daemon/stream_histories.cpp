#include "daemon/stream_histories.h"

namespace fq::daemon {

std::shared_ptr<StreamHistories::Slot> StreamHistories::slot_of(const std::string& stream_id) {
  const std::lock_guard<std::mutex> lock(mutex_);
  std::shared_ptr<Slot>& s = slots_[stream_id];
  if (!s) s = std::make_shared<Slot>();
  count_.store(slots_.size(), std::memory_order_relaxed);
  return s;
}

void StreamHistories::forget(const std::string& stream_id) {
  const std::lock_guard<std::mutex> lock(mutex_);
  slots_.erase(stream_id);
  count_.store(slots_.size(), std::memory_order_relaxed);
}

}  // namespace fq::daemon
