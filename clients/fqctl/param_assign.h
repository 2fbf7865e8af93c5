// `fqctl set STREAM key=value…` and `fqctl params STREAM`: parameters by their wire field
// names, found through protobuf reflection, so that every field of the control messages is
// settable and printable without a hand-kept list of keys.
#pragma once

#include <google/protobuf/message.h>

#include <string>
#include <utility>
#include <vector>

#include "common/status.h"
#include "wire/fq.pb.h"

namespace fq::client {

/// Applies one `key=value` to a SetParams request: a field of its `params` message, else
/// a field of SetParams itself (`compute`, `result_form`). Floats, integers, booleans (true/false/1/0/
/// on/off) and enum names in any case ("bf", "euclidean", "filter_and_cluster").
/// kInvalidArgument naming the key or value, with the valid keys for an unknown key.
Status assign_param(const std::string& key_value, wire::SetParams& out);

/// A get_params/set_params reply as `fqctl params` prints it: every field of `params`, then
/// the reply's fields named as SetParams' own settable fields (compute, result_form).
std::vector<std::pair<std::string, std::string>> describe_params(const wire::ControlReply& r);

/// Every scalar field of a message (unset optional ones left out) as (name, value) pairs,
/// enums as lower-case names.
std::vector<std::pair<std::string, std::string>> describe_fields(const google::protobuf::Message& m);

}  // namespace fq::client
