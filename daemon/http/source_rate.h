// A token bucket per source address, for what a peer may try only a few times a second (a
// login, a TLS handshake): each source may spend `burst` at once and then `per_second`. The
// sources kept are bounded: past `max_sources`, sources whose bucket has filled again are
// forgotten (they would start full anyway), and while none has, every new source shares one
// bucket, so that a flood of addresses costs bounded memory and still gets no more than the rate.
// Thread-safe.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>

namespace fq::daemon {

class SourceRate {
 public:
  SourceRate(double per_second, double burst, size_t max_sources = 4096)
      : per_second_(per_second), burst_(burst), max_sources_(max_sources) {}

  /// True when `source` may go ahead at `now_ns` (steady clock), spending one token; otherwise
  /// false with `retry_after_s`, the whole seconds until it has a token again (at least 1).
  bool allow(const std::string& source, int64_t now_ns, int& retry_after_s);
  /// allow() at the steady clock's now.
  bool allow_now(const std::string& source, int& retry_after_s);

  /// Sources with a bucket of their own (for tests of the bound).
  size_t sources() const;

 private:
  struct Bucket {
    double tokens = 0;
    int64_t at_ns = 0;
  };
  void refill(Bucket& b, int64_t now_ns) const;
  Bucket& bucket_of(const std::string& source, int64_t now_ns);

  const double per_second_, burst_;
  const size_t max_sources_;
  mutable std::mutex mutex_;
  std::map<std::string, Bucket> buckets_;
  Bucket shared_;  ///< for new sources while max_sources_ hold tokens
  bool shared_started_ = false;
};

}  // namespace fq::daemon
