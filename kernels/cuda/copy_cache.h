// The device copies a pass keeps of what streams taking turns on one engine read (fqd): the
// spatial track's histories (temporal_pass.cuh), track A's tables and averaged inputs
// (id_pass.cuh). A few copies, each with the pass's count when last used.
#pragma once

#include <cstddef>

namespace fq::cuda {

/// The copy of `copies` that `holds` accepts (held = true), else the least recently used one
/// (the smallest `used`; held = false), which the caller fills.
template <class Copy, size_t N, class Holds>
Copy& copy_holding(Copy (&copies)[N], Holds holds, bool& held) {
  Copy* oldest = &copies[0];
  for (Copy& c : copies) {
    if (holds(c)) {
      held = true;
      return c;
    }
    if (c.used < oldest->used) oldest = &c;
  }
  held = false;
  return *oldest;
}

}  // namespace fq::cuda
