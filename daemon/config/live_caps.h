// The caps fqd runs with now ([caps] of the configuration): read by every thread, replaced whole
// when SIGHUP reloads the file. Readers take a snapshot and use it for one message or request.
#pragma once

#include <memory>
#include <mutex>

#include "daemon/config/config.h"

namespace fq::daemon {

class LiveCaps {
 public:
  explicit LiveCaps(const Caps& caps) : caps_(std::make_shared<const Caps>(caps)) {}

  std::shared_ptr<const Caps> get() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return caps_;
  }
  void set(const Caps& caps) {
    auto fresh = std::make_shared<const Caps>(caps);
    std::lock_guard<std::mutex> lock(mutex_);
    caps_ = std::move(fresh);
  }

 private:
  mutable std::mutex mutex_;
  std::shared_ptr<const Caps> caps_;
};

}  // namespace fq::daemon
