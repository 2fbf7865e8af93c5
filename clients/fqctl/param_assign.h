// `fqctl set STREAM key=value…` and `fqctl params STREAM`: the parameters by the rows of the
// parameter table (core/param_table.h: names, kinds and enum names as configs spell them, "qf+",
// "auto"), and SetParams' own settings (compute, result_form, budget_ms, the output encoding)
// by protobuf reflection on their field names, so neither needs a hand-kept list of keys.
#pragma once

#include <google/protobuf/message.h>

#include <string>
#include <utility>
#include <vector>

#include "common/status.h"
#include "wire/fq.pb.h"

namespace fq::client {

/// Applies one `key=value` to a SetParams request: a field of its `params` message, else
/// a field of SetParams itself (`compute`, `result_form`, `budget_ms`...). Floats, integers, booleans
/// (true/false/1/0/on/off) and enum names in any case ("qf+", "BF", "euclidean", "filter_and_cluster").
/// kInvalidArgument naming the key or value; for an unknown key, the nearest keys when one is
/// near enough to be a typo of it, and the valid keys.
Status assign_param(const std::string& key_value, wire::SetParams& out);

/// A get_params/set_params reply as `fqctl params` prints it: every field of `params`, then
/// the reply's fields named as SetParams' own settable fields (compute, result_form).
std::vector<std::pair<std::string, std::string>> describe_params(const wire::ControlReply& r);

}  // namespace fq::client
