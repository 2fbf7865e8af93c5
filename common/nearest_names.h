// "Did you mean": the known names nearest to a mistyped one, for the messages that refuse a
// name (fqctl set's keys, the control socket's stream ids). Distance is the optimal string
// alignment distance: an insertion, a deletion, a substitution or a swap of two neighbouring
// characters each counts 1, so "cma0" is 1 from "cam0".
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace fq {

/// Edits that turn `a` into `b`.
size_t edit_distance(std::string_view a, std::string_view b);

/// The names nearest to `typed` (ties all, in their order, at most 3) when they are near enough
/// to be a typo of it: at most a third of the longer one's length apart (at least 1), and fewer
/// edits than `typed` has characters. Empty when none is, or `typed` is itself among them.
std::vector<std::string> nearest_names(std::string_view typed, const std::vector<std::string>& names);

/// " (did you mean 'a'?)", " (did you mean 'a' or 'b'?)", or "" when no name is near.
std::string did_you_mean(std::string_view typed, const std::vector<std::string>& names);

}  // namespace fq
