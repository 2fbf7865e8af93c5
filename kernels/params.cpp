#include "kernels/params.h"

#include <cmath>
#include <sstream>
#include <string>

namespace fq {

const char* status_code_name(StatusCode code) {
  switch (code) {
    case StatusCode::kOk: return "ok";
    case StatusCode::kInvalidArgument: return "invalid argument";
    case StatusCode::kInvalidInput: return "invalid input";
    case StatusCode::kUnavailable: return "unavailable";
    case StatusCode::kInternal: return "internal error";
  }
  return "unknown";
}

namespace {

// "-1" or "0.25" rather than std::to_string's "-1.000000".
std::string show(float v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

// Upper bound on any sigma: beyond it the neighbourhood is the whole mesh anyway and
// the grid visitor would only waste time.
constexpr float kMaxSigma = 1e4f;

Status check_sigma(const char* name, float v, bool zero_means_default) {
  if (std::isnan(v)) return invalid_argument(std::string(name) + " is NaN");
  if (zero_means_default && v == 0.f) return {};
  if (!(v > 0.f)) return invalid_argument(std::string(name) + " must be > 0 (got " + show(v) + ")");
  if (!(v <= kMaxSigma))
    return invalid_argument(std::string(name) + " must be at most 1e4 mean edge lengths (got " +
                            show(v) + ")");
  return {};
}

}  // namespace

bool parse_cluster_geometry(const std::string& s, ClusterGeometry& out) {
  if (s == "auto")
    out = ClusterGeometry::kAuto;
  else if (s == "input")
    out = ClusterGeometry::kInput;
  else if (s == "filtered")
    out = ClusterGeometry::kFiltered;
  else
    return false;
  return true;
}

const char* cluster_geometry_name(ClusterGeometry g) {
  return g == ClusterGeometry::kInput ? "input" : g == ClusterGeometry::kFiltered ? "filtered" : "auto";
}

Status validate(const Params& p) {
  if (!p.filter && !p.cluster) return invalid_argument("nothing to compute: enable filter and/or cluster");
  const FilterParams& f = p.f;
  for (Status s : {check_sigma("sigma_s", f.sigma_s, false), check_sigma("sigma_r", f.sigma_r, false),
                   check_sigma("sigma_b", f.sigma_b, true), check_sigma("sigma_n", f.sigma_n, true)}) {
    if (!s.ok()) return s;
  }
  if (!(f.tikhonov >= 0.f && f.tikhonov <= 1e3f))
    return invalid_argument("tikhonov must be in [0, 1000] (got " + show(f.tikhonov) + ")");
  if (p.cluster) {
    for (Status s : {check_sigma("sigma_d", p.c.sigma_d, false), check_sigma("sigma_q", p.c.sigma_q, false)}) {
      if (!s.ok()) return s;
    }
    if (p.c.sticky_rings > 64)
      return invalid_argument("sticky_rings must be at most 64 (got " + std::to_string(p.c.sticky_rings) + ")");
    if (!(p.c.theta > 0.f && p.c.theta <= 1.f))
      return invalid_argument("theta must be in (0, 1] (got " + show(p.c.theta) + ")");
  }
  return {};
}

}  // namespace fq
