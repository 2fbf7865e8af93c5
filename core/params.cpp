#include "core/params.h"

#include <cmath>
#include <sstream>
#include <string>
#include <utility>

#include "common/pair_table.h"

namespace fq {

namespace {

constexpr std::pair<FilterMethod, const char*> kFilterMethodNames[] = {
    {FilterMethod::kQuadricRefined, "qf+"}, {FilterMethod::kQuadric, "qf"}, {FilterMethod::kBilateral, "bf"}};
constexpr std::pair<ClusterMethod, const char*> kClusterMethodNames[] = {
    {ClusterMethod::kQuadric, "quadric"}, {ClusterMethod::kEuclidean, "euclidean"}};

constexpr std::pair<ClusterGeometry, const char*> kClusterGeometryNames[] = {
    {ClusterGeometry::kAuto, "auto"},
    {ClusterGeometry::kInput, "input"},
    {ClusterGeometry::kFiltered, "filtered"}};

constexpr const auto& names_of(FilterMethod) { return kFilterMethodNames; }
constexpr const auto& names_of(ClusterMethod) { return kClusterMethodNames; }

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

const char* filter_method_name(FilterMethod m) { return method_name(m); }

bool parse_filter_method(const std::string& s, FilterMethod& out) {
  const std::optional<FilterMethod> m = parse_method<FilterMethod>(s);
  if (m) out = *m;
  return m.has_value();
}

Status validate(const RefineParams& r) {
  // Beyond 10 mean edges of noise the triangulation says nothing about the surface any more.
  if (!(r.known_noise >= 0.f && r.known_noise <= 10.f))
    return invalid_argument("known_noise must be in [0, 10] mean edge lengths (0 = estimated; got " + show(r.known_noise) + ")");
  if (!(r.strength >= 0.f && r.strength <= 10.f))
    return invalid_argument("strength must be in [0, 10] (got " + show(r.strength) + ")");
  return {};
}

bool parse_cluster_geometry(const std::string& s, ClusterGeometry& out) {
  const std::optional<ClusterGeometry> g = first_of(kClusterGeometryNames, s);
  if (g) out = *g;
  return g.has_value();
}

const char* cluster_geometry_name(ClusterGeometry g) {
  return second_of(kClusterGeometryNames, g).value_or("auto");
}

std::vector<std::string> cluster_geometry_names() {
  std::vector<std::string> out;
  for (const auto& entry : kClusterGeometryNames) out.emplace_back(entry.second);
  return out;
}

Status validate(const Params& p) {
  if (!p.filter && !p.cluster) return invalid_argument("nothing to compute: enable filter and/or cluster");
  const FilterParams& f = p.filtering;
  for (const Status& s : {check_sigma("sigma_s", f.sigma_s, false), check_sigma("sigma_r", f.sigma_r, false),
                          check_sigma("sigma_b", f.sigma_b, true), check_sigma("sigma_n", f.sigma_n, true)})
    FQ_RETURN_IF_ERROR(s);
  if (!(f.tikhonov >= 0.f && f.tikhonov <= 1e3f))
    return invalid_argument("tikhonov must be in [0, 1000] (got " + show(f.tikhonov) + ")");
  if (Status s = validate(f.refine); !s.ok()) return s;
  if (!(f.temporal >= 0.f && f.temporal <= 1.f))
    return invalid_argument("temporal must be in [0, 1] (got " + show(f.temporal) + ")");
  if (p.cluster) {
    for (const Status& s :
         {check_sigma("sigma_d", p.clustering.sigma_d, false), check_sigma("sigma_q", p.clustering.sigma_q, false)})
      FQ_RETURN_IF_ERROR(s);
    if (p.clustering.sticky_rings > 64)
      return invalid_argument("sticky_rings must be at most 64 (got " + std::to_string(p.clustering.sticky_rings) + ")");
    if (!(p.clustering.theta > 0.f && p.clustering.theta <= 1.f))
      return invalid_argument("theta must be in (0, 1] (got " + show(p.clustering.theta) + ")");
  }
  return {};
}

const char* method_name(FilterMethod m) { return second_of(kFilterMethodNames, m).value_or("?"); }
const char* method_name(ClusterMethod m) { return second_of(kClusterMethodNames, m).value_or("?"); }

template <typename Method>
std::optional<Method> parse_method(std::string_view name) {
  return first_of(names_of(Method{}), name);
}
template std::optional<FilterMethod> parse_method<FilterMethod>(std::string_view);
template std::optional<ClusterMethod> parse_method<ClusterMethod>(std::string_view);

template <typename Method>
std::vector<std::string> method_names() {
  std::vector<std::string> out;
  for (const auto& entry : names_of(Method{})) out.emplace_back(entry.second);
  return out;
}
template std::vector<std::string> method_names<FilterMethod>();
template std::vector<std::string> method_names<ClusterMethod>();

std::string join_names(const std::vector<std::string>& names, std::string_view separator, bool quoted) {
  std::string out;
  for (const std::string& n : names) {
    if (!out.empty()) out += separator;
    if (quoted) out += '"';
    out += n;
    if (quoted) out += '"';
  }
  return out;
}

}  // namespace fq
