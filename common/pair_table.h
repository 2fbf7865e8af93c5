// Lookups in small constant tables of pairs (an enum and its name, a wire enum and the
// library's): one table serves both directions, so each mapping is written once.
#pragma once

#include <cstddef>
#include <optional>
#include <utility>

namespace fq {

/// The second of the first pair whose first equals `key`; nullopt when none does.
template <class A, class B, std::size_t N, class Key>
constexpr std::optional<B> second_of(const std::pair<A, B> (&table)[N], const Key& key) {
  for (const auto& [a, b] : table)
    if (a == key) return b;
  return std::nullopt;
}

/// The first of the first pair whose second equals `key`; nullopt when none does.
template <class A, class B, std::size_t N, class Key>
constexpr std::optional<A> first_of(const std::pair<A, B> (&table)[N], const Key& key) {
  for (const auto& [a, b] : table)
    if (b == key) return a;
  return std::nullopt;
}

}  // namespace fq
