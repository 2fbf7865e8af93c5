#include "daemon/stream_histories.h"

namespace fq::daemon {

std::shared_ptr<StreamHistories::Slot> StreamHistories::slot_of(const std::string& stream_id) {
  const std::lock_guard<std::mutex> lock(mutex_);
  std::shared_ptr<Slot>& s = slots_[stream_id];
  if (!s) s = std::make_shared<Slot>();
  return s;
}

void StreamHistories::forget(const std::string& stream_id) {
  const std::lock_guard<std::mutex> lock(mutex_);
  slots_.erase(stream_id);
}

size_t StreamHistories::size() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return slots_.size();
}

}  // namespace fq::daemon
