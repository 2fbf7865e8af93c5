#include "daemon/config/stream_settings.h"

#include <cmath>
#include <optional>
#include <utility>

#include "common/pair_table.h"
#include "wire/header_codec.h"

namespace fq::daemon {

namespace {

constexpr std::pair<ResultForm, const char*> kResultFormNames[] = {{ResultForm::kPositions, "positions"},
                                                                   {ResultForm::kMesh, "mesh"}};

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

Status validate(const StreamSettings& s) {
  // The clustering parameters are checked even when the stream only filters: a frame or a
  // control request may switch clustering on at any time.
  Params all = s.params;
  all.filter = all.cluster = true;
  FQ_RETURN_IF_ERROR(fq::validate(all));
  if (!(s.budget_ms > 0.0 && std::isfinite(s.budget_ms)))
    return invalid_argument("budget_ms must be > 0 (got " + std::to_string(s.budget_ms) + ")");
  if (s.output.position_bits < 8 || s.output.position_bits > 30)
    return invalid_argument("output position_bits must be in [8, 30] (got " +
                            std::to_string(s.output.position_bits) + ")");
  if (s.output.encode_speed < 0 || s.output.encode_speed > 10 || s.output.decode_speed < 0 ||
      s.output.decode_speed > 10)
    return invalid_argument("output encode_speed and decode_speed must be in [0, 10]");
  if (s.output.chunks > 256)
    return invalid_argument("output chunks must be \"same\" or 1..256 (got " +
                            std::to_string(s.output.chunks) + ")");
  return {};
}

}  // namespace fq::daemon
