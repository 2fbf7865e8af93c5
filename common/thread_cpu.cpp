#include "common/thread_cpu.h"

#include <ctime>

namespace fq {
namespace {

thread_local CpuScope* t_scope = nullptr;

}  // namespace

int64_t thread_cpu_ns() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return int64_t(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

CpuScope::CpuScope(CpuAccount& account) : account_(account), outer_(t_scope), start_ns_(thread_cpu_ns()) {
  // The outer scope's share ends here and starts again when this one ends.
  if (outer_ != nullptr) outer_->account_.fetch_add(start_ns_ - outer_->start_ns_, std::memory_order_relaxed);
  t_scope = this;
}

CpuScope::~CpuScope() {
  const int64_t now = thread_cpu_ns();
  account_.fetch_add(now - start_ns_, std::memory_order_relaxed);
  if (outer_ != nullptr) outer_->start_ns_ = now;
  t_scope = outer_;
}

CpuAccount* CpuScope::current() { return t_scope != nullptr ? &t_scope->account_ : nullptr; }

}  // namespace fq
