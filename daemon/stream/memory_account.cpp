#include "daemon/stream/memory_account.h"

#include <utility>

namespace fq::daemon {

const char* memory_kind_name(MemoryKind k) {
  switch (k) {
    case MemoryKind::kHistory:
      return "history";
    case MemoryKind::kLabelTrack:
      return "label_track";
    case MemoryKind::kLatest:
      return "latest";
    case MemoryKind::kQueued:
    case MemoryKind::kCount:
      break;
  }
  return "queued";
}

void MemoryAccount::set_budget(uint64_t bytes) {
  const std::lock_guard<std::mutex> lock(mutex_);
  budget_ = bytes;
}

uint64_t MemoryAccount::budget() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return budget_;
}

void MemoryAccount::set_shedder(Shedder shedder) {
  const std::lock_guard<std::mutex> lock(mutex_);
  shedder_ = std::move(shedder);
}

bool MemoryAccount::try_add(MemoryKind kind, uint64_t bytes) {
  const std::lock_guard<std::mutex> lock(mutex_);
  if (budget_ != 0 && (bytes > budget_ || total_ > budget_ - bytes)) return false;
  bytes_[static_cast<size_t>(kind)] += bytes;
  total_ += bytes;
  if (total_ > peak_) peak_ = total_;
  return true;
}

bool MemoryAccount::charge(MemoryKind kind, uint64_t bytes, Shed upto, const void* keep) {
  if (try_add(kind, bytes)) return true;
  Shedder shed;
  uint64_t need = 0;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    shed = shedder_;
    need = bytes > budget_ ? bytes : total_ + bytes - budget_;
  }
  // A charge larger than the whole budget never fits: nothing is shed for it.
  if (upto == Shed::kNone || !shed || bytes > budget()) return false;
  shed(need, upto, keep);
  return try_add(kind, bytes);
}

void MemoryAccount::credit(MemoryKind kind, uint64_t bytes) {
  const std::lock_guard<std::mutex> lock(mutex_);
  uint64_t& b = bytes_[static_cast<size_t>(kind)];
  const uint64_t n = bytes < b ? bytes : b;  // never below zero, whatever a holder credits
  b -= n;
  total_ -= n;
}

uint64_t MemoryAccount::bytes(MemoryKind kind) const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return bytes_[static_cast<size_t>(kind)];
}

uint64_t MemoryAccount::total() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return total_;
}

uint64_t MemoryAccount::peak() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return peak_;
}

MemoryCharge::MemoryCharge(MemoryCharge&& o) noexcept
    : account_(std::exchange(o.account_, nullptr)), kind_(o.kind_), bytes_(std::exchange(o.bytes_, 0)) {}

MemoryCharge& MemoryCharge::operator=(MemoryCharge&& o) noexcept {
  if (this != &o) {
    release();
    account_ = std::exchange(o.account_, nullptr);
    kind_ = o.kind_;
    bytes_ = std::exchange(o.bytes_, 0);
  }
  return *this;
}

bool MemoryCharge::set(MemoryAccount* account, MemoryKind kind, uint64_t bytes, Shed upto, const void* keep) {
  if (!account) return true;
  if (account_ != account || kind_ != kind) release();
  account_ = account;
  kind_ = kind;
  if (bytes <= bytes_) {
    account->credit(kind, bytes_ - bytes);
    bytes_ = bytes;
    return true;
  }
  if (!account->charge(kind, bytes - bytes_, upto, keep)) return false;
  bytes_ = bytes;
  return true;
}

void MemoryCharge::release() {
  if (account_ && bytes_ > 0) account_->credit(kind_, bytes_);
  bytes_ = 0;
}

}  // namespace fq::daemon
