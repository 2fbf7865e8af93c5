#include "clients/fqctl/param_assign.h"

#include <google/protobuf/text_format.h>

#include <algorithm>
#include <cctype>
#include <optional>

#include "common/nearest_names.h"
#include "core/param_table.h"
#include "wire/header_codec.h"

namespace fq::client {
namespace {

namespace pb = google::protobuf;

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

std::string upper(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::toupper(c); });
  return s;
}

// A number or boolean of SetParams' own fields (budget_ms, position_bits...), read as the
// parameter table reads its rows.
Status parse_scalar(const pb::FieldDescriptor* f, ParamKind kind, const std::string& value, double& out) {
  ParamRow row{};
  row.name = f->name().c_str();
  row.kind = kind;
  return parse_param(row, value, out);
}

// Fields a user may set: the stream's settings, scalars and enums that the reply carries under
// the same name (not the stream id, nested messages, or `create`, which is about the request).
bool settable(const pb::FieldDescriptor* f) {
  return f && !f->is_repeated() && f->cpp_type() != pb::FieldDescriptor::CPPTYPE_MESSAGE &&
         f->cpp_type() != pb::FieldDescriptor::CPPTYPE_STRING &&
         wire::ControlReply::descriptor()->FindFieldByName(f->name()) != nullptr;
}

std::vector<std::string> valid_keys() {
  std::vector<std::string> keys;
  for (const ParamRow& row : param_table())
    if (row.on(kWire)) keys.emplace_back(row.name);
  const pb::Descriptor* d = wire::SetParams::descriptor();
  for (int i = 0; i < d->field_count(); ++i)
    if (settable(d->field(i))) keys.push_back(d->field(i)->name());
  return keys;
}

// A value named *_DEFAULT means "unset" on the wire (COMPUTE_DEFAULT, MODE_DEFAULT); any other
// value is a choice, zero included (ResultForm's POSITIONS).
bool choosable(const pb::EnumValueDescriptor* v) {
  const std::string& n = v->name();
  return !(n.size() >= 8 && n.compare(n.size() - 8, 8, "_DEFAULT") == 0);
}

Status set_enum(pb::Message& m, const pb::FieldDescriptor* f, const std::string& value) {
  const pb::EnumValueDescriptor* v = f->enum_type()->FindValueByName(upper(value));
  if (!v || !choosable(v)) {
    std::string names;
    for (int i = 0; i < f->enum_type()->value_count(); ++i)
      if (choosable(f->enum_type()->value(i)))
        names += (names.empty() ? "" : ", ") + lower(f->enum_type()->value(i)->name());
    return invalid_argument(f->name() + " must be one of " + names + " (got \"" + value + "\")");
  }
  m.GetReflection()->SetEnum(&m, f, v);
  return {};
}

Status set_field(pb::Message& m, const pb::FieldDescriptor* f, const std::string& value) {
  const pb::Reflection* r = m.GetReflection();
  double d = 0;
  switch (f->cpp_type()) {
    case pb::FieldDescriptor::CPPTYPE_ENUM:
      return set_enum(m, f, value);
    case pb::FieldDescriptor::CPPTYPE_BOOL:
      FQ_RETURN_IF_ERROR(parse_scalar(f, ParamKind::kBool, value, d));
      r->SetBool(&m, f, d != 0.0);
      return {};
    case pb::FieldDescriptor::CPPTYPE_FLOAT:
    case pb::FieldDescriptor::CPPTYPE_DOUBLE:
      FQ_RETURN_IF_ERROR(parse_scalar(f, ParamKind::kFloat, value, d));
      if (f->cpp_type() == pb::FieldDescriptor::CPPTYPE_FLOAT)
        r->SetFloat(&m, f, static_cast<float>(d));
      else
        r->SetDouble(&m, f, d);
      return {};
    case pb::FieldDescriptor::CPPTYPE_UINT32:
      FQ_RETURN_IF_ERROR(parse_scalar(f, ParamKind::kUint, value, d));
      r->SetUInt32(&m, f, static_cast<uint32_t>(d));
      return {};
    default:
      return invalid_argument(f->name() + " cannot be set from the command line");
  }
}

std::string field_text(const pb::Message& m, const pb::FieldDescriptor* f) {
  const pb::Reflection* r = m.GetReflection();
  switch (f->cpp_type()) {
    case pb::FieldDescriptor::CPPTYPE_ENUM:
      return lower(r->GetEnum(m, f)->name());
    case pb::FieldDescriptor::CPPTYPE_BOOL:
      return r->GetBool(m, f) ? "true" : "false";
    case pb::FieldDescriptor::CPPTYPE_STRING:
      return r->GetString(m, f);
    default: {
      // Short round-trip text for numbers (2, 0.05, 1e-06) via protobuf's own printer.
      std::string out;
      pb::TextFormat::PrintFieldValueToString(m, f, -1, &out);
      return out;
    }
  }
}

}  // namespace

Status assign_param(const std::string& key_value, wire::SetParams& out) {
  const size_t eq = key_value.find('=');
  if (eq == std::string::npos || eq == 0)
    return invalid_argument("expected key=value, got \"" + key_value + "\"");
  const std::string key = lower(key_value.substr(0, eq)), value = key_value.substr(eq + 1);
  if (const ParamRow* row = find_param(key); row && row->on(kWire)) {
    double v = 0;
    // Enum names in any case ("BF" for "bf"), as for SetParams' own enums below.
    FQ_RETURN_IF_ERROR(parse_param(*row, row->kind == ParamKind::kEnum ? lower(value) : value, v));
    wire::set_wire_value(*row, v, *out.mutable_params());
    return {};
  }
  if (const pb::FieldDescriptor* f = out.GetDescriptor()->FindFieldByName(key); settable(f))
    return set_field(out, f, value);
  const std::vector<std::string> keys = valid_keys();
  std::string list;
  for (const std::string& k : keys) list += (list.empty() ? "" : ", ") + k;
  return invalid_argument("unknown parameter '" + key + "'" + did_you_mean(key, keys) + "; one of: " + list);
}

std::vector<std::pair<std::string, std::string>> describe_params(const wire::ControlReply& r) {
  // The reply carries each settable field of SetParams outside `params` (compute,
  // result_form) under the same name: found by reflection, as assign_param finds keys.
  std::vector<std::pair<std::string, std::string>> out;
  for (const ParamRow& row : param_table()) {
    std::optional<double> v;
    if (row.on(kWire) && wire::wire_value(row, r.params(), v).ok() && v)
      out.emplace_back(row.name, format_param(row, *v));
  }
  const pb::Descriptor* set = wire::SetParams::descriptor();
  for (int i = 0; i < set->field_count(); ++i)
    if (settable(set->field(i)))
      if (const pb::FieldDescriptor* f = r.GetDescriptor()->FindFieldByName(set->field(i)->name()))
        out.emplace_back(f->name(), field_text(r, f));
  return out;
}

}  // namespace fq::client
