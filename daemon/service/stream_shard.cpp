#include "daemon/service/stream_shard.h"

#include <charconv>

#include "daemon/config/service_config.h"

namespace fq::daemon {
namespace {

bool parse_count(std::string_view s, uint32_t& out) {
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && end == s.data() + s.size() && !s.empty();
}

}  // namespace

uint32_t stream_hash(std::string_view id) {
  uint32_t h = 2166136261u;
  for (const char c : id) {
    h ^= static_cast<unsigned char>(c);
    h *= 16777619u;
  }
  return h;
}

uint32_t shard_of(std::string_view id, uint32_t count) { return count == 0 ? 0 : stream_hash(id) % count; }

Status parse_shard(const std::string& text, uint32_t& index, uint32_t& count) {
  const size_t slash = text.rfind('/');
  const std::string_view whole(text);
  std::string_view k = slash == std::string::npos ? whole : whole.substr(0, slash);
  // A pod name (fqd-2): its ordinal is what follows the last '-' (a name, not a sign).
  const size_t dash = k.rfind('-');
  if (dash != std::string_view::npos) k = dash == 0 ? std::string_view() : k.substr(dash + 1);
  if (slash == std::string::npos || !parse_count(k, index) || !parse_count(whole.substr(slash + 1), count) ||
      count == 0 || index >= count)
    return invalid_argument(
        "--shard must be K/N with 0 <= K < N, K an ordinal or a pod name ending in -K (got \"" + text +
        "\")");
  return {};
}

std::vector<std::string> keep_shard(SubIngestConfig& sub, uint32_t index, uint32_t count) {
  std::vector<std::string> kept;
  for (const std::string& id : sub.streams)
    if (shard_of(id, count) == index) kept.push_back(id);
  sub.streams = kept;
  if (kept.empty()) sub.connect.clear();
  return kept;
}

}  // namespace fq::daemon
