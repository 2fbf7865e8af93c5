#include "common/nearest_names.h"

#include <algorithm>
#include <cstdint>

namespace fq {
namespace {

constexpr size_t kMaxSuggestions = 3;

}  // namespace

size_t edit_distance(std::string_view a, std::string_view b) {
  // Three rows of the dynamic programme: the swap looks two rows back.
  std::vector<size_t> before(b.size() + 1), previous(b.size() + 1), row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) previous[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t substitute = previous[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
      row[j] = std::min({previous[j] + 1, row[j - 1] + 1, substitute});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        row[j] = std::min(row[j], before[j - 2] + 1);
    }
    std::swap(before, previous);
    std::swap(previous, row);
  }
  return previous[b.size()];
}

std::vector<std::string> nearest_names(std::string_view typed, const std::vector<std::string>& names) {
  std::vector<std::string> nearest;
  size_t best = SIZE_MAX;
  for (const std::string& name : names) {
    const size_t d = edit_distance(typed, name);
    if (d == 0) return {};
    const size_t reach = std::max<size_t>(1, std::max(typed.size(), name.size()) / 3);
    if (d > reach || d >= typed.size() || d > best) continue;
    if (d < best) nearest.clear(), best = d;
    if (nearest.size() < kMaxSuggestions) nearest.push_back(name);
  }
  return nearest;
}

std::string did_you_mean(std::string_view typed, const std::vector<std::string>& names) {
  const std::vector<std::string> nearest = nearest_names(typed, names);
  if (nearest.empty()) return {};
  std::string text = " (did you mean ";
  for (size_t i = 0; i < nearest.size(); ++i)
    text += (i == 0 ? "'" : i + 1 == nearest.size() ? " or '" : ", '") + nearest[i] + "'";
  return text + "?)";
}

}  // namespace fq
