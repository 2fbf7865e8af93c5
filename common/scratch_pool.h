// Scratch objects kept from call to call for whichever thread needs one, in place of a
// thread_local cache: a thread borrows one for a chunk or a frame and gives it back when the
// lease ends, and release() frees those not borrowed. A thread_local cache lived as long as
// its thread (the shared pool's threads live as long as the process) and no other thread
// could free it; this one is freed by whoever decides memory should go back (fqd when idle).
// Borrowing takes a lock once per lease: nothing next to encoding or decoding a chunk.
#pragma once

#include <cstddef>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

#include "common/non_copyable.h"

namespace fq {

template <class T>
class ScratchPool : NonCopyable {
 public:
  /// A borrowed object; back to the pool (with its capacity) when the lease ends.
  class Lease : NonCopyable {
   public:
    Lease(ScratchPool& pool, std::unique_ptr<T> item) : pool_(pool), item_(std::move(item)) {}
    ~Lease() { pool_.put_back(std::move(item_)); }
    T& operator*() const { return *item_; }
    T* operator->() const { return item_.get(); }

   private:
    ScratchPool& pool_;
    std::unique_ptr<T> item_;
  };

  ScratchPool() = default;

  /// A kept object (as its last borrower left it), or a new one.
  Lease borrow() {
    std::unique_ptr<T> item;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!free_.empty()) {
        item = std::move(free_.back());
        free_.pop_back();
      }
    }
    if (!item) item = std::make_unique<T>();
    return Lease(*this, std::move(item));
  }

  /// Frees every object not borrowed now; returns how many. Borrowed ones come back later.
  size_t release() {
    std::vector<std::unique_ptr<T>> gone;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      gone.swap(free_);
    }
    return gone.size();  // freed here, outside the lock
  }

 private:
  void put_back(std::unique_ptr<T> item) {
    std::lock_guard<std::mutex> lock(mutex_);
    free_.push_back(std::move(item));
  }

  std::mutex mutex_;
  std::vector<std::unique_ptr<T>> free_;
};

}  // namespace fq
