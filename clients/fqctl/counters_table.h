// The tables `fqctl counters` prints and `fqctl watch` redraws, each within 80 columns: one
// row per stream with its output rate and the counts of frames that did not make it, then
// one row per stream with the p50/p99 of each stage.
#pragma once

#include <map>
#include <string>

#include "wire/fq.pb.h"

namespace fq::client {

/// frames_out per stream at the previous refresh, to turn counts into a rate.
using OutCounts = std::map<std::string, uint64_t>;

/// The table for one counters reply. `seconds` since `previous` was taken (0 on the first
/// refresh: fps shows "-"); `previous` is updated to this reply's counts.
std::string counters_table(const wire::ControlReply& reply, double seconds, OutCounts& previous);

}  // namespace fq::client
