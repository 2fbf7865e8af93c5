#include "common/thread_pool.h"

#include <pthread.h>

#include <algorithm>
#include <atomic>
#include <exception>
#include <system_error>

#include "common/thread_cpu.h"

namespace fq {

/// One run() call. Lives on its caller's stack: the caller unqueues it and waits until no
/// worker is inside before returning.
struct ThreadPool::Job {
  RangeFn fn;
  void* ctx;
  size_t count, grain;
  size_t max_workers;
  CpuAccount* account;  ///< the caller's CpuScope: pool threads charge their share to it
  std::atomic<size_t> next{0};
  size_t joined = 1;  ///< worker ids handed out (the caller is 0); under the pool mutex
  size_t inside = 0;  ///< workers working on it; under the pool mutex

  bool exhausted() const { return next.load(std::memory_order_relaxed) >= count; }
  void work(size_t worker) {
    for (size_t b = next.fetch_add(grain); b < count; b = next.fetch_add(grain))
      fn(ctx, b, std::min(count, b + grain), worker);
  }
};

ThreadPool::ThreadPool(int workers) {
  threads_.reserve(static_cast<size_t>(std::max(workers, 0)));
  for (int i = 0; i < workers; ++i) {
    try {
      threads_.emplace_back([this] { worker_loop(); });
    } catch (const std::system_error&) {
      break;  // resource limits: fewer workers, loops still complete on their callers
    }
  }
}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  work_.notify_all();
  for (auto& t : threads_) t.join();
}

ThreadPool& ThreadPool::shared() {
  // Never destroyed: joining at static destruction would deadlock if exit() were called from a
  // pool thread, and could race a loop still running on another thread. The workers sleep in
  // their wait and end with the process.
  static ThreadPool* pool =
      new ThreadPool(static_cast<int>(std::max(1u, std::thread::hardware_concurrency())) - 1);
  return *pool;
}

void ThreadPool::run_ranges(size_t count, int max_workers, size_t grain, RangeFn fn, void* ctx) {
  if (count == 0) return;
  grain = std::max<size_t>(grain, 1);
  const size_t ranges = (count + grain - 1) / grain;
  const size_t workers = std::min({size_t(std::max(max_workers, 1)), ranges, threads_.size() + 1});
  if (workers <= 1) {
    fn(ctx, 0, count, 0);
    return;
  }
  Job job{fn, ctx, count, grain, workers, CpuScope::current()};
  {
    std::lock_guard lock(mutex_);
    jobs_.push_back(&job);
  }
  for (size_t i = 1; i < workers; ++i) work_.notify_one();
  std::exception_ptr failed;
  try {
    job.work(0);
  } catch (...) {  // fn must not throw; if it does, no worker may be left inside this job
    failed = std::current_exception();
    job.next.store(job.count);
  }
  std::unique_lock lock(mutex_);
  if (auto it = std::find(jobs_.begin(), jobs_.end(), &job); it != jobs_.end()) jobs_.erase(it);
  done_.wait(lock, [&] { return job.inside == 0; });
  if (failed) std::rethrow_exception(failed);
}

void ThreadPool::worker_loop() {
  pthread_setname_np(pthread_self(), "fq-pool");  // perf and top -H show whose threads these are
  std::unique_lock lock(mutex_);
  for (;;) {
    work_.wait(lock, [&] { return stop_ || !jobs_.empty(); });
    if (jobs_.empty()) return;  // stop_, nothing left
    Job* job = jobs_.front();
    if (job->exhausted()) {  // its caller finishes it and unqueues it; no need to join
      jobs_.pop_front();
      continue;
    }
    const size_t worker = job->joined++;
    if (job->joined == job->max_workers) jobs_.pop_front();
    ++job->inside;
    lock.unlock();
    if (job->account != nullptr) {
      const CpuScope scope(*job->account);
      job->work(worker);
    } else {
      job->work(worker);
    }
    lock.lock();
    if (--job->inside == 0) done_.notify_all();
  }
}

}  // namespace fq
