// A valid value other than the default for each row of the parameter table, so that a test
// walking the table sees every row's value arrive (a default would arrive even if the row
// were ignored).
#pragma once

#include <cmath>
#include <string>

#include "core/param_table.h"

namespace fq::test {

inline double other_value(const ParamRow& row) {
  const double now = row.get(Params{});
  switch (row.kind) {
    case ParamKind::kBool:
      return now != 0.0 ? 0.0 : 1.0;
    case ParamKind::kEnum:
      for (const ParamChoice& c : row.choices)
        if (c.value != static_cast<int>(now)) return c.value;
      return now;
    case ParamKind::kUint:
    case ParamKind::kFloat:
      break;
  }
  double v = row.lo + (row.hi - row.lo) * 0.375;  // inside every range, open or closed
  if (row.kind == ParamKind::kUint) v = std::floor(v);
  return v == now ? row.hi : v;
}

/// A filter method's name ("qf+"), as the parameter table spells it, for test messages.
inline std::string mode_name(FilterMethod m) {
  return format_param(*find_param("mode"), static_cast<int>(m));
}

}  // namespace fq::test
