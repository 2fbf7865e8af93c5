#include "daemon/stream_settings.h"

#include <cmath>

namespace fq::daemon {

bool parse_compute(const std::string& s, Params& inout) {
  if (s == "filter")
    inout.filter = true, inout.cluster = false;
  else if (s == "cluster")
    inout.filter = false, inout.cluster = true;
  else if (s == "filter_and_cluster")
    inout.filter = true, inout.cluster = true;
  else
    return false;
  return true;
}

const char* compute_name(const Params& p) {
  if (p.filter && p.cluster) return "filter_and_cluster";
  if (p.cluster) return "cluster";
  return "filter";
}

bool parse_result_form(const std::string& s, ResultForm& out) {
  if (s == "positions")
    out = ResultForm::kPositions;
  else if (s == "mesh")
    out = ResultForm::kMesh;
  else
    return false;
  return true;
}

const char* result_form_name(ResultForm f) { return f == ResultForm::kMesh ? "mesh" : "positions"; }
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
