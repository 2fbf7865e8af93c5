// ParamOverrides / Compute <-> fq::Params: the parameters by the table's rows (core/param_table.h),
// each field found by its name through protobuf reflection.
#include <optional>
#include <string>
#include <string_view>
#include <tuple>
#include <utility>

#include "common/pair_table.h"
#include "core/param_table.h"
#include "wire/header_codec.h"

namespace fq::wire {
namespace {

/// Params::filter and Params::cluster of each compute mode.
constexpr std::pair<Compute, std::pair<bool, bool>> kComputes[] = {
    {FILTER, {true, false}}, {CLUSTER, {false, true}}, {FILTER_AND_CLUSTER, {true, true}}};
constexpr std::pair<Compute, const char*> kComputeNames[] = {
    {FILTER, "filter"}, {CLUSTER, "cluster"}, {FILTER_AND_CLUSTER, "filter_and_cluster"}};

/// Sets `out` to what `w` stands for in `table`; the enum's DEFAULT (0) keeps `out`.
/// kInvalidArgument, naming `what`, for a value outside the wire enum.
template <class Wire, class Native, size_t N>
fq::Status set_from_wire(const std::pair<Wire, Native> (&table)[N], Wire w, const char* what, Native& out) {
  if (w == Wire{}) return {};
  const std::optional<Native> native = second_of(table, w);
  if (!native)
    return invalid_argument(std::string(what) + " " + std::to_string(w) + " is not a " +
                            google::protobuf::GetEnumDescriptor<Wire>()->name());
  out = *native;
  return {};
}

namespace pb = google::protobuf;

// Each row's field is found by its name (tests/wire/param_table_wire_test.cpp checks that every
// kWire row has a ParamOverrides field of that name and a matching type).
const pb::FieldDescriptor* field_of(const fq::ParamRow& row) {
  return ParamOverrides::descriptor()->FindFieldByName(row.name);
}

template <class Wire, class Native>
Wire wire_enum(const char* row, Native v) {
  return static_cast<Wire>(fq::choice_wire(*fq::find_param(row), static_cast<int>(v)).value_or(0));
}

}  // namespace

FilterMode to_wire(fq::FilterMethod m) { return wire_enum<FilterMode>("mode", m); }
ClusterMethodWire to_wire(fq::ClusterMethod m) { return wire_enum<ClusterMethodWire>("cluster_method", m); }
ClusterGeometryWire to_wire(fq::ClusterGeometry g) {
  return wire_enum<ClusterGeometryWire>("cluster_geometry", g);
}

fq::Status wire_value(const fq::ParamRow& row, const ParamOverrides& o, std::optional<double>& out) {
  out.reset();
  const pb::FieldDescriptor* f = field_of(row);
  const pb::Reflection* r = o.GetReflection();
  if (!f || !r->HasField(o, f)) return {};
  switch (f->cpp_type()) {
    case pb::FieldDescriptor::CPPTYPE_FLOAT:
      out = r->GetFloat(o, f);
      return {};
    case pb::FieldDescriptor::CPPTYPE_UINT32:
      out = r->GetUInt32(o, f);
      return {};
    case pb::FieldDescriptor::CPPTYPE_BOOL:
      out = r->GetBool(o, f) ? 1.0 : 0.0;
      return {};
    case pb::FieldDescriptor::CPPTYPE_ENUM: {
      const int w = r->GetEnumValue(o, f);
      if (w == 0) return {};  // the enum's *_DEFAULT: keep the stream's value
      const std::optional<int> v = fq::choice_value(row, w);
      if (!v)
        return invalid_argument(std::string(row.name) + " " + std::to_string(w) + " is not a " +
                                f->enum_type()->name());
      out = *v;
      return {};
    }
    default:
      return invalid_argument(std::string(row.name) + " has no wire type fq knows");
  }
}

void set_wire_value(const fq::ParamRow& row, double value, ParamOverrides& o) {
  const pb::FieldDescriptor* f = field_of(row);
  if (!f) return;
  const pb::Reflection* r = o.GetReflection();
  switch (f->cpp_type()) {
    case pb::FieldDescriptor::CPPTYPE_FLOAT:
      r->SetFloat(&o, f, static_cast<float>(value));
      break;
    case pb::FieldDescriptor::CPPTYPE_UINT32:
      r->SetUInt32(&o, f, static_cast<uint32_t>(value));
      break;
    case pb::FieldDescriptor::CPPTYPE_BOOL:
      r->SetBool(&o, f, value != 0.0);
      break;
    case pb::FieldDescriptor::CPPTYPE_ENUM:
      r->SetEnumValue(&o, f, fq::choice_wire(row, static_cast<int>(value)).value_or(0));
      break;
    default:
      break;
  }
}

fq::Status apply_overrides(const ParamOverrides& o, fq::Params& inout) {
  fq::Params p = inout;  // all or nothing: a bad enum leaves `inout` untouched
  for (const fq::ParamRow& row : fq::param_table()) {
    if (!row.on(fq::kWire)) continue;
    std::optional<double> v;
    FQ_RETURN_IF_ERROR(wire_value(row, o, v));
    if (v) row.set(p, *v);
  }
  inout = p;
  return {};
}

fq::Status apply_compute(Compute c, fq::Params& inout) {
  std::pair<bool, bool> flags{inout.filter, inout.cluster};
  FQ_RETURN_IF_ERROR(set_from_wire(kComputes, c, "compute", flags));
  std::tie(inout.filter, inout.cluster) = flags;
  return {};
}

Compute compute_of(const fq::Params& p) {
  return first_of(kComputes, std::pair{p.filter, p.cluster}).value_or(FILTER);
}

const char* compute_name(Compute c) { return second_of(kComputeNames, c).value_or("filter"); }

std::optional<Compute> compute_from_name(std::string_view name) { return first_of(kComputeNames, name); }

void params_to_wire(const fq::Params& p, ParamOverrides& out) {
  for (const fq::ParamRow& row : fq::param_table())
    if (row.on(fq::kWire)) set_wire_value(row, row.get(p), out);
}

}  // namespace fq::wire
