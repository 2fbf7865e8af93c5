#include "clients/fqctl/param_assign.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <google/protobuf/text_format.h>

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

// Whole-string number parsing: "2.5x" or "" is an error, not 2.5 or 0.
bool parse_double(const std::string& s, double& out) {
  if (s.empty()) return false;
  char* end = nullptr;
  out = std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size() && std::isfinite(out);
}

bool parse_bool(const std::string& s, bool& out) {
  const std::string v = lower(s);
  if (v == "true" || v == "1" || v == "on" || v == "yes") return out = true, true;
  if (v == "false" || v == "0" || v == "off" || v == "no") return out = false, true;
  return false;
}

// Fields a user may set: scalars and enums (not the stream id or nested messages).
bool settable(const pb::FieldDescriptor* f) {
  return f && !f->is_repeated() && f->cpp_type() != pb::FieldDescriptor::CPPTYPE_MESSAGE &&
         f->cpp_type() != pb::FieldDescriptor::CPPTYPE_STRING;
}

std::string valid_keys(const wire::SetParams& q) {
  std::string keys;
  for (const pb::Descriptor* d : {q.params().GetDescriptor(), q.GetDescriptor()})
    for (int i = 0; i < d->field_count(); ++i)
      if (settable(d->field(i))) keys += (keys.empty() ? "" : ", ") + d->field(i)->name();
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
  bool b = false;
  switch (f->cpp_type()) {
    case pb::FieldDescriptor::CPPTYPE_ENUM:
      return set_enum(m, f, value);
    case pb::FieldDescriptor::CPPTYPE_BOOL:
      if (!parse_bool(value, b)) return invalid_argument(f->name() + " must be true or false (got \"" + value + "\")");
      r->SetBool(&m, f, b);
      return {};
    case pb::FieldDescriptor::CPPTYPE_FLOAT:
    case pb::FieldDescriptor::CPPTYPE_DOUBLE:
      if (!parse_double(value, d)) return invalid_argument(f->name() + " must be a number (got \"" + value + "\")");
      if (f->cpp_type() == pb::FieldDescriptor::CPPTYPE_FLOAT)
        r->SetFloat(&m, f, static_cast<float>(d));
      else
        r->SetDouble(&m, f, d);
      return {};
    case pb::FieldDescriptor::CPPTYPE_INT32:
    case pb::FieldDescriptor::CPPTYPE_UINT32:
    case pb::FieldDescriptor::CPPTYPE_INT64:
    case pb::FieldDescriptor::CPPTYPE_UINT64:
      if (!parse_double(value, d) || d != std::floor(d) || d < 0 || d > 4294967295.0)
        return invalid_argument(f->name() + " must be a whole number (got \"" + value + "\")");
      if (f->cpp_type() == pb::FieldDescriptor::CPPTYPE_INT32) r->SetInt32(&m, f, static_cast<int32_t>(d));
      if (f->cpp_type() == pb::FieldDescriptor::CPPTYPE_UINT32) r->SetUInt32(&m, f, static_cast<uint32_t>(d));
      if (f->cpp_type() == pb::FieldDescriptor::CPPTYPE_INT64) r->SetInt64(&m, f, static_cast<int64_t>(d));
      if (f->cpp_type() == pb::FieldDescriptor::CPPTYPE_UINT64) r->SetUInt64(&m, f, static_cast<uint64_t>(d));
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
  pb::Message* params = out.mutable_params();
  if (const pb::FieldDescriptor* f = params->GetDescriptor()->FindFieldByName(key); settable(f))
    return set_field(*params, f, value);
  if (const pb::FieldDescriptor* f = out.GetDescriptor()->FindFieldByName(key); settable(f))
    return set_field(out, f, value);
  return invalid_argument("unknown parameter '" + key + "'; one of: " + valid_keys(out));
}

std::vector<std::pair<std::string, std::string>> describe_params(const wire::ControlReply& r) {
  // The reply carries each settable field of SetParams outside `params` (compute,
  // result_form) under the same name: found by reflection, as assign_param finds keys.
  std::vector<std::pair<std::string, std::string>> out = describe_fields(r.params());
  const pb::Descriptor* set = wire::SetParams::descriptor();
  for (int i = 0; i < set->field_count(); ++i)
    if (settable(set->field(i)))
      if (const pb::FieldDescriptor* f = r.GetDescriptor()->FindFieldByName(set->field(i)->name()))
        out.emplace_back(f->name(), field_text(r, f));
  return out;
}

std::vector<std::pair<std::string, std::string>> describe_fields(const pb::Message& m) {
  // Every field in declaration order: a proto3 field at its default (sigma_b = 0) is a
  // real value here, not an absent one; only explicitly optional unset fields are skipped.
  std::vector<std::pair<std::string, std::string>> out;
  const pb::Descriptor* d = m.GetDescriptor();
  for (int i = 0; i < d->field_count(); ++i) {
    const pb::FieldDescriptor* f = d->field(i);
    if (f->is_repeated() || f->cpp_type() == pb::FieldDescriptor::CPPTYPE_MESSAGE) continue;
    if (f->has_presence() && !m.GetReflection()->HasField(m, f)) continue;
    out.emplace_back(f->name(), field_text(m, f));
  }
  return out;
}

}  // namespace fq::client
