// The viewer's login sessions: /login with the right token opens one and sets its id as the
// cookie, so that the cookie is not the bearer token itself (a cookie read from a browser's
// store, a proxy log or a shared screen gives a session that expires, not the token). Ids are
// 32 random bytes (OpenSSL's RAND_bytes) in hex, kept in memory only: a restart, or a reload
// that changes the token, ends every session. Bounded: the oldest session goes when
// kMaxSessions are open. Thread-safe.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>

namespace fq::daemon {

class HttpSessions {
 public:
  static constexpr size_t kMaxSessions = 1024;

  explicit HttpSessions(double lifetime_s = 12 * 3600.0)
      : lifetime_ns_(static_cast<int64_t>(lifetime_s * 1e9)) {}

  /// A new session valid from `now_ns` (steady clock) for the lifetime; empty when no random
  /// bytes could be had.
  std::string open(int64_t now_ns);
  /// True for the id of a session open at `now_ns` (compared in constant time).
  bool valid(const std::string& id, int64_t now_ns) const;
  /// Ends every session.
  void clear();
  size_t size() const;

 private:
  const int64_t lifetime_ns_;
  mutable std::mutex mutex_;
  std::map<std::string, int64_t> expiry_;  ///< id -> end (steady ns)
};

}  // namespace fq::daemon
