#include "daemon/config/stream_settings.h"

#include <cmath>
#include <cstdio>
#include <optional>
#include <utility>

#include "common/pair_table.h"
#include "wire/header_codec.h"

namespace fq::daemon {

namespace {

constexpr std::pair<ResultForm, const char*> kResultFormNames[] = {{ResultForm::kPositions, "positions"},
                                                                   {ResultForm::kMesh, "mesh"}};

// A bound as written in the config ("0.001", "1000000", "8").
std::string format_bound(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.15g", v);
  return buf;
}

}  // namespace

bool parse_compute(const std::string& s, Params& inout) {
  const std::optional<wire::Compute> c = wire::compute_from_name(s);
  return c && wire::apply_compute(*c, inout).ok();
}

const char* compute_name(const Params& p) { return wire::compute_name(wire::compute_of(p)); }

bool parse_result_form(const std::string& s, ResultForm& out) {
  const std::optional<ResultForm> f = first_of(kResultFormNames, s);
  if (f) out = *f;
  return f.has_value();
}

const char* result_form_name(ResultForm f) { return second_of(kResultFormNames, f).value_or("positions"); }
wire::ResultForm to_wire(ResultForm f) { return f == ResultForm::kMesh ? wire::MESH : wire::POSITIONS; }
ResultForm from_wire(wire::ResultForm f) { return f == wire::MESH ? ResultForm::kMesh : ResultForm::kPositions; }

namespace {

// "name must be in [lo, hi] (got v)" when v is outside r (or NaN).
Status check_range(const SettingRange& r, double v) {
  if (v >= r.lo && v <= r.hi) return {};
  char got[64];
  std::snprintf(got, sizeof got, "%.17g", v);
  return invalid_argument(std::string(r.name) + " must be in [" + format_bound(r.lo) + ", " +
                          format_bound(r.hi) + "] (got " + got + ")");
}

}  // namespace

Status validate(const StreamSettings& s) {
  // The clustering parameters are checked even when the stream only filters: a frame or a
  // control request may switch clustering on at any time.
  Params all = s.params;
  all.filter = all.cluster = true;
  FQ_RETURN_IF_ERROR(fq::validate(all));
  FQ_RETURN_IF_ERROR(check_range(kBudgetRange, s.budget_ms));
  FQ_RETURN_IF_ERROR(check_range(kPositionBitsRange, s.output.position_bits));
  FQ_RETURN_IF_ERROR(check_range(kEncodeSpeedRange, s.output.encode_speed));
  FQ_RETURN_IF_ERROR(check_range(kDecodeSpeedRange, s.output.decode_speed));
  if (s.output.chunks != 0) FQ_RETURN_IF_ERROR(check_range(kChunksRange, s.output.chunks));
  return {};
}

}  // namespace fq::daemon
