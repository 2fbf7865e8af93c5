#include "daemon/http/http_sessions.h"

#include <openssl/crypto.h>
#include <openssl/rand.h>

#include <algorithm>
#include <array>
#include <cstdio>

namespace fq::daemon {

std::string HttpSessions::open(int64_t now_ns) {
  std::array<unsigned char, 32> bytes{};
  if (RAND_bytes(bytes.data(), static_cast<int>(bytes.size())) != 1) return {};
  std::string id;
  for (unsigned char b : bytes) {
    char hex[3];
    std::snprintf(hex, sizeof hex, "%02x", b);
    id += hex;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  for (auto it = expiry_.begin(); it != expiry_.end();)
    it = it->second <= now_ns ? expiry_.erase(it) : std::next(it);
  if (expiry_.size() >= kMaxSessions)
    expiry_.erase(std::min_element(expiry_.begin(), expiry_.end(),
                                   [](const auto& a, const auto& b) { return a.second < b.second; }));
  expiry_[id] = now_ns + lifetime_ns_;
  return id;
}

bool HttpSessions::valid(const std::string& id, int64_t now_ns) const {
  std::lock_guard<std::mutex> lock(mutex_);
  // Every stored id is compared whole, in constant time, so the answer's timing says nothing
  // about how much of a guess was right (a map lookup compares byte by byte).
  bool found = false;
  for (const auto& [known, end] : expiry_)
    if (known.size() == id.size() && CRYPTO_memcmp(known.data(), id.data(), id.size()) == 0 && end > now_ns)
      found = true;
  return found;
}

void HttpSessions::clear() {
  std::lock_guard<std::mutex> lock(mutex_);
  expiry_.clear();
}

size_t HttpSessions::size() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return expiry_.size();
}

}  // namespace fq::daemon
