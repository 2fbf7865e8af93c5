#include "daemon/config/stream_setting_table.h"

#include <fmt/format.h>

#include <cstdio>
#include <optional>
#include <type_traits>
#include <vector>

#include "common/member_value.h"
#include "daemon/config/echo_value.h"
#include "daemon/config/toml_reader.h"

namespace fq::daemon {
namespace {

using S = StreamSettings;
using O = OutputEncoding;
using K = SettingKind;

// clang-format off
constexpr StreamSettingRow kRows[] = {
    {.name = "budget_ms", .table = nullptr, .kind = K::kDouble,
     .get = get_member<&S::budget_ms>, .set = set_member<&S::budget_ms>, .lo = 0.001, .hi = 1e6,
     .zero = nullptr, .choices = {},
     .help = "Receive-to-publish budget in ms: older frames are dropped, later results flagged LATE"},
    {.name = "result_form", .table = "output", .kind = K::kEnum,
     .get = get_member<&S::output, &O::form>, .set = set_member<&S::output, &O::form>, .lo = 0, .hi = 0,
     .zero = nullptr, .choices = kResultForms,
     .help = "What a result carries: the filtered positions only, or the whole mesh"},
    {.name = "position_bits", .table = "output", .kind = K::kInt,
     .get = get_member<&S::output, &O::position_bits>, .set = set_member<&S::output, &O::position_bits>,
     .lo = 8, .hi = 30, .zero = nullptr, .choices = {},
     .help = "Draco position quantization of results; high enough not to undo the smoothing"},
    {.name = "chunks", .table = "output", .kind = K::kUint,
     .get = get_member<&S::output, &O::chunks>, .set = set_member<&S::output, &O::chunks>,
     .lo = 1, .hi = 256, .zero = "same", .choices = {},
     .help = "Result chunks; same (0 on the wire): as many as the input frame"},
    {.name = "encode_speed", .table = "output", .kind = K::kInt,
     .get = get_member<&S::output, &O::encode_speed>, .set = set_member<&S::output, &O::encode_speed>,
     .lo = 0, .hi = 10, .zero = nullptr, .choices = {},
     .help = "Draco encoder speed (10: sequential, fastest; 0: smallest)"},
    {.name = "decode_speed", .table = "output", .kind = K::kInt,
     .get = get_member<&S::output, &O::decode_speed>, .set = set_member<&S::output, &O::decode_speed>,
     .lo = 0, .hi = 10, .zero = nullptr, .choices = {},
     .help = "Draco decoder speed the encoder aims for"},
};
// clang-format on

// A bound as written in the config ("0.001", "1000000", "8").
std::string format_bound(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.15g", v);
  return buf;
}

// The native value of an enum row's name, if it has one.
const ParamChoice* choice_named(const StreamSettingRow& row, std::string_view name) {
  for (const ParamChoice& c : row.choices)
    if (name == c.name) return &c;
  return nullptr;
}

// The integer rows' text: a TOML integer in [lo, hi], or the `zero` word.
void read_count(TomlReader& r, const StreamSettingRow& row, StreamSettings& s) {
  const toml::node* n = r.raw(row.name);
  if (!n) return;
  const auto lo = static_cast<int64_t>(row.lo), hi = static_cast<int64_t>(row.hi);
  if (auto str = n->value_exact<std::string>(); str && *str == row.zero)
    row.set(s, 0);
  else if (auto v = n->value_exact<int64_t>(); v && *v >= lo && *v <= hi)
    row.set(s, static_cast<double>(*v));
  else
    r.fail(row.name, std::string("must be \"") + row.zero + "\" or an integer in [" + std::to_string(lo) +
                         ", " + std::to_string(hi) + "]");
}

void read_enum(TomlReader& r, const StreamSettingRow& row, StreamSettings& s) {
  std::string name = format_setting(row, row.get(s));
  r.read(row.name, name);
  if (const ParamChoice* c = choice_named(row, name)) {
    row.set(s, c->value);
    return;
  }
  r.fail(row.name,
         "must be " + choice_names(row.choices, " or ", true) + " (got \"" + echo_value(name) + "\")");
}

// A number in [lo, hi]: TomlReader's typed read, which names the range in its message.
template <class T>
void read_number(TomlReader& r, const StreamSettingRow& row, StreamSettings& s) {
  auto v = static_cast<T>(row.get(s));
  if constexpr (std::is_floating_point_v<T>)
    r.read(row.name, v, row.lo, row.hi);
  else
    r.read(row.name, v, static_cast<int64_t>(row.lo), static_cast<int64_t>(row.hi));
  row.set(s, v);
}

void read_row(TomlReader& r, const StreamSettingRow& row, StreamSettings& s) {
  switch (row.kind) {
    case K::kDouble:
      return read_number<double>(r, row, s);
    case K::kInt:
      return read_number<int>(r, row, s);
    case K::kUint:
      return read_count(r, row, s);
    case K::kEnum:
      return read_enum(r, row, s);
  }
}

namespace pb = google::protobuf;

// The number SetParams carries for `row`, if it carries one.
std::optional<double> wire_value(const StreamSettingRow& row, const wire::SetParams& q) {
  const pb::FieldDescriptor* f = wire::SetParams::descriptor()->FindFieldByName(row.name);
  const pb::Reflection* r = q.GetReflection();
  if (!f || !r->HasField(q, f)) return std::nullopt;
  switch (f->cpp_type()) {
    case pb::FieldDescriptor::CPPTYPE_DOUBLE:
      return r->GetDouble(q, f);
    case pb::FieldDescriptor::CPPTYPE_UINT32: {
      const uint32_t v = r->GetUInt32(q, f);
      // A value beyond int's range becomes -1, which the range check refuses.
      return row.kind == K::kInt && v > 1'000'000u ? -1.0 : static_cast<double>(v);
    }
    case pb::FieldDescriptor::CPPTYPE_ENUM: {
      // A number outside the enum (proto3 keeps it) stands for the first choice.
      return choice_value(row.choices, r->GetEnumValue(q, f)).value_or(row.choices.front().value);
    }
    default:
      return std::nullopt;
  }
}

void set_wire_value(const StreamSettingRow& row, double v, wire::ControlReply& out) {
  const pb::FieldDescriptor* f = wire::ControlReply::descriptor()->FindFieldByName(row.name);
  const pb::Reflection* r = out.GetReflection();
  if (!f) return;
  switch (f->cpp_type()) {
    case pb::FieldDescriptor::CPPTYPE_DOUBLE:
      r->SetDouble(&out, f, v);
      return;
    case pb::FieldDescriptor::CPPTYPE_UINT32:
      r->SetUInt32(&out, f, static_cast<uint32_t>(v));
      return;
    case pb::FieldDescriptor::CPPTYPE_ENUM:
      if (const std::optional<int> w = choice_wire(row.choices, static_cast<int>(v)))
        r->SetEnumValue(&out, f, *w);
      return;
    default:
      return;
  }
}

}  // namespace

std::string StreamSettingRow::key() const {
  return table ? std::string(table) + "." + name : std::string(name);
}

std::span<const StreamSettingRow> stream_setting_table() { return kRows; }

std::string format_setting(const StreamSettingRow& row, double value) {
  if (row.zero && value == 0) return row.zero;
  switch (row.kind) {
    case K::kDouble:
      return fmt::format("{}", value);
    case K::kInt:
    case K::kUint:
      return std::to_string(static_cast<int64_t>(value));
    case K::kEnum:
      for (const ParamChoice& c : row.choices)
        if (c.value == static_cast<int>(value)) return c.name;
      return row.choices.front().name;
  }
  return {};
}

Status check_setting(const StreamSettingRow& row, double value) {
  if (row.kind == K::kEnum || (row.zero && value == 0) || (value >= row.lo && value <= row.hi)) return {};
  char got[64];
  std::snprintf(got, sizeof got, "%.17g", value);
  return invalid_argument(row.key() + " must be in [" + format_bound(row.lo) + ", " + format_bound(row.hi) +
                          "] (got " + got + ")");
}

void read_settings(TomlReader& r, const char* table, StreamSettings& s) {
  for (const StreamSettingRow& row : kRows)
    if (std::string_view(row.table ? row.table : "") == std::string_view(table ? table : ""))
      read_row(r, row, s);
}

void settings_from_wire(const wire::SetParams& q, StreamSettings& s) {
  for (const StreamSettingRow& row : kRows)
    if (const std::optional<double> v = wire_value(row, q)) row.set(s, *v);
}

void settings_to_wire(const StreamSettings& s, wire::ControlReply& r) {
  for (const StreamSettingRow& row : kRows) set_wire_value(row, row.get(s), r);
}

}  // namespace fq::daemon
