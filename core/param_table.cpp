#include "core/param_table.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "common/member_value.h"

namespace fq {
namespace {

template <auto E>
constexpr int as_int = static_cast<int>(E);

// The wire keeps fq.proto's numbers (QF = 1, BF = 2, QF_PLUS = 3); the names are the config's.
constexpr ParamChoice kModes[] = {{"qf+", as_int<FilterMethod::kQuadricRefined>, 3},
                                  {"qf", as_int<FilterMethod::kQuadric>, 1},
                                  {"bf", as_int<FilterMethod::kBilateral>, 2}};
constexpr ParamChoice kClusterMethods[] = {{"quadric", as_int<ClusterMethod::kQuadric>, 1},
                                           {"euclidean", as_int<ClusterMethod::kEuclidean>, 2}};
constexpr ParamChoice kGeometries[] = {{"auto", as_int<ClusterGeometry::kAuto>, 1},
                                       {"input", as_int<ClusterGeometry::kInput>, 2},
                                       {"filtered", as_int<ClusterGeometry::kFiltered>, 3}};

double effective_sigma_b(const Params& p) { return p.filtering.effective_sigma_b(); }
double effective_sigma_n(const Params& p) { return p.filtering.effective_sigma_n(); }

constexpr unsigned kEverySurface = kFqfilter | kToml | kWire | kReport;
constexpr const char* kEdges = " mean edge lengths";
// Beyond 1e4 mean edges a neighbourhood is the whole mesh anyway and the grid visitor would
// only waste time; beyond 10 mean edges of noise the triangulation says nothing about the
// surface any more; 1e7 clusters or vertices per cluster is past any frame fqd accepts.
constexpr double kMaxSigma = 1e4, kMaxNoise = 10, kMaxCount = 1e7;

using G = ParamGroup;
using K = ParamKind;
using P = Params;
using F = FilterParams;
using C = ClusterParams;
using R = RefineParams;

// clang-format off
constexpr ParamRow kRows[] = {
    {.name = "filter", .toml = nullptr, .python = nullptr, .group = G::kCompute, .kind = K::kBool,
     .get = get_member<&P::filter>, .set = set_member<&P::filter>, .lo = 0, .hi = 1, .lo_open = false,
     .zero = nullptr, .unit = "", .choices = {}, .surfaces = kReport,
     .help = "Move the vertices (fqd: its compute setting)"},
    {.name = "cluster", .toml = nullptr, .python = nullptr, .group = G::kCompute, .kind = K::kBool,
     .get = get_member<&P::cluster>, .set = set_member<&P::cluster>, .lo = 0, .hi = 1, .lo_open = false,
     .zero = nullptr, .unit = "", .choices = {}, .surfaces = kFqfilter | kReport,
     .help = "Compute a cluster label per vertex (written with the output; fqd: its compute setting)"},

    {.name = "mode", .toml = "method", .python = nullptr, .group = G::kFilter, .kind = K::kEnum,
     .get = get_member<&P::filtering, &F::method>, .set = set_member<&P::filtering, &F::method>,
     .lo = 0, .hi = 0, .lo_open = false, .zero = nullptr, .unit = "", .choices = kModes,
     .surfaces = kEverySurface | kPythonFilter,
     .help = "Filter: qf+ (fq's filter, its strength derived from the noise it estimates), qf (the paper's "
             "filtered quadrics exactly) or bf (bilateral baseline)"},
    {.name = "sigma_s", .toml = nullptr, .python = nullptr, .group = G::kFilter, .kind = K::kFloat,
     .get = get_member<&P::filtering, &F::sigma_s>, .set = set_member<&P::filtering, &F::sigma_s>,
     .lo = 0, .hi = kMaxSigma, .lo_open = true, .zero = nullptr, .unit = kEdges, .choices = {},
     .surfaces = kEverySurface | kPythonFilter | kPythonCluster,
     .help = "qf, bf and the clustering: spatial extent of the diffusion, in mean edge lengths"},
    {.name = "sigma_r", .toml = nullptr, .python = nullptr, .group = G::kFilter, .kind = K::kFloat,
     .get = get_member<&P::filtering, &F::sigma_r>, .set = set_member<&P::filtering, &F::sigma_r>,
     .lo = 0, .hi = kMaxSigma, .lo_open = true, .zero = nullptr, .unit = kEdges, .choices = {},
     .surfaces = kEverySurface | kPythonFilter | kPythonCluster,
     .help = "qf and the clustering: range extent (RMS quadric distance), in mean edge lengths"},
    {.name = "sigma_b", .toml = nullptr, .python = nullptr, .group = G::kFilter, .kind = K::kFloat,
     .get = get_member<&P::filtering, &F::sigma_b>, .set = set_member<&P::filtering, &F::sigma_b>,
     .lo = 0, .hi = kMaxSigma, .lo_open = true, .zero = "sigma_s / 2", .unit = kEdges, .choices = {},
     .surfaces = kEverySurface | kPythonFilter | kPythonCluster,
     .help = "Finest detail captured by the neighbourhood quadrics; 0 = sigma_s / 2",
     .effective = effective_sigma_b},
    {.name = "sigma_n", .toml = nullptr, .python = nullptr, .group = G::kFilter, .kind = K::kFloat,
     .get = get_member<&P::filtering, &F::sigma_n>, .set = set_member<&P::filtering, &F::sigma_n>,
     .lo = 0, .hi = kMaxSigma, .lo_open = true, .zero = "sigma_s / 2", .unit = kEdges, .choices = {},
     .surfaces = kEverySurface | kPythonFilter,
     .help = "Normal smoothing of the constrained update; 0 = sigma_s / 2", .effective = effective_sigma_n},
    {.name = "constrained", .toml = nullptr, .python = nullptr, .group = G::kFilter, .kind = K::kBool,
     .get = get_member<&P::filtering, &F::constrained>, .set = set_member<&P::filtering, &F::constrained>,
     .lo = 0, .hi = 1, .lo_open = false, .zero = nullptr, .unit = "", .choices = {},
     .surfaces = kEverySurface | kPythonFilter, .help = "Move vertices along the smoothed normal only"},
    {.name = "tikhonov", .toml = nullptr, .python = nullptr, .group = G::kFilter, .kind = K::kFloat,
     .get = get_member<&P::filtering, &F::tikhonov>, .set = set_member<&P::filtering, &F::tikhonov>,
     .lo = 0, .hi = 1000, .lo_open = false, .zero = "the paper's solver", .unit = "", .choices = {},
     .surfaces = kEverySurface | kPythonFilter,
     .help = "Pull toward the current position, relative to tr(A)/3; 0 = the paper's solver"},

    {.name = "known_noise", .toml = nullptr, .python = nullptr, .group = G::kNoise, .kind = K::kFloat,
     .get = get_member<&P::filtering, &F::refine, &R::known_noise>,
     .set = set_member<&P::filtering, &F::refine, &R::known_noise>,
     .lo = 0, .hi = kMaxNoise, .lo_open = false, .zero = "estimated", .unit = kEdges, .choices = {},
     .surfaces = kEverySurface | kPythonFilter,
     .help = "qf+: noise to filter for, in mean edge lengths (along the normal); 0 = estimated per frame"},
    {.name = "strength", .toml = nullptr, .python = nullptr, .group = G::kNoise, .kind = K::kFloat,
     .get = get_member<&P::filtering, &F::refine, &R::strength>,
     .set = set_member<&P::filtering, &F::refine, &R::strength>,
     .lo = 0, .hi = kMaxNoise, .lo_open = false, .zero = nullptr, .unit = "", .choices = {},
     .surfaces = kEverySurface | kPythonFilter,
     .help = "qf+: multiplies the noise the filter's strengths come from (2: as for twice the noise; 0: no "
             "filtering)"},

    {.name = "temporal", .toml = nullptr, .python = nullptr, .group = G::kTemporal, .kind = K::kFloat,
     .get = get_member<&P::filtering, &F::temporal>, .set = set_member<&P::filtering, &F::temporal>,
     .lo = 0, .hi = 1, .lo_open = false, .zero = "each frame alone", .unit = "", .choices = {},
     .surfaces = kEverySurface | kPythonStream,
     .help = "qf+ on a stream of frames: how far a vertex may be pulled to the last result's surface where "
             "that surface did not move, in [0, 1]; 0 = each frame alone"},

    {.name = "cluster_method", .toml = "method", .python = "method", .group = G::kCluster, .kind = K::kEnum,
     .get = get_member<&P::clustering, &C::method>, .set = set_member<&P::clustering, &C::method>,
     .lo = 0, .hi = 0, .lo_open = false, .zero = nullptr, .unit = "", .choices = kClusterMethods,
     .surfaces = kEverySurface | kPythonCluster,
     .help = "quadric (the paper) or euclidean (plain quick shift)"},
    {.name = "sigma_d", .toml = nullptr, .python = nullptr, .group = G::kCluster, .kind = K::kFloat,
     .get = get_member<&P::clustering, &C::sigma_d>, .set = set_member<&P::clustering, &C::sigma_d>,
     .lo = 0, .hi = kMaxSigma, .lo_open = true, .zero = nullptr, .unit = kEdges, .choices = {},
     .surfaces = kEverySurface | kPythonCluster,
     .help = "Spatial extent of score and proximity, in mean edge lengths"},
    {.name = "sigma_q", .toml = nullptr, .python = nullptr, .group = G::kCluster, .kind = K::kFloat,
     .get = get_member<&P::clustering, &C::sigma_q>, .set = set_member<&P::clustering, &C::sigma_q>,
     .lo = 0, .hi = kMaxSigma, .lo_open = true, .zero = nullptr, .unit = kEdges, .choices = {},
     .surfaces = kEverySurface | kPythonCluster,
     .help = "Range extent of the clustering (RMS quadric distance)"},
    {.name = "theta", .toml = nullptr, .python = nullptr, .group = G::kCluster, .kind = K::kFloat,
     .get = get_member<&P::clustering, &C::theta>, .set = set_member<&P::clustering, &C::theta>,
     .lo = 0, .hi = 1, .lo_open = true, .zero = nullptr, .unit = "", .choices = {},
     .surfaces = kEverySurface | kPythonCluster, .help = "In (0, 1]; higher gives fewer, larger clusters"},
    {.name = "target_clusters", .toml = nullptr, .python = nullptr, .group = G::kCluster, .kind = K::kUint,
     .get = get_member<&P::clustering, &C::target_clusters>,
     .set = set_member<&P::clustering, &C::target_clusters>,
     .lo = 0, .hi = kMaxCount, .lo_open = false, .zero = "use theta", .unit = "", .choices = {},
     .surfaces = kEverySurface | kPythonCluster,
     .help = "Choose theta per frame to give about this many clusters; 0 = use theta"},
    {.name = "cluster_geometry", .toml = "geometry", .python = "geometry", .group = G::kCluster,
     .kind = K::kEnum, .get = get_member<&P::clustering, &C::geometry>,
     .set = set_member<&P::clustering, &C::geometry>,
     .lo = 0, .hi = 0, .lo_open = false, .zero = nullptr, .unit = "", .choices = kGeometries,
     .surfaces = kEverySurface | kPythonCluster,
     .help = "Quadrics the clustering uses: input (the paper), filtered (after a constrained filter) or auto "
             "(filtered with target_clusters)"},
    {.name = "min_cluster_size", .toml = nullptr, .python = nullptr, .group = G::kCluster, .kind = K::kUint,
     .get = get_member<&P::clustering, &C::min_cluster_size>,
     .set = set_member<&P::clustering, &C::min_cluster_size>,
     .lo = 0, .hi = kMaxCount, .lo_open = false, .zero = "off", .unit = "", .choices = {},
     .surfaces = kEverySurface | kPythonCluster,
     .help = "Split clusters into mesh-connected parts and merge parts under this many vertices; 0 = off"},
    // fqd only: they need a stream's frames.
    {.name = "track_ids", .toml = nullptr, .python = nullptr, .group = G::kCluster, .kind = K::kBool,
     .get = get_member<&P::clustering, &C::track_ids>, .set = set_member<&P::clustering, &C::track_ids>,
     .lo = 0, .hi = 1, .lo_open = false, .zero = nullptr, .unit = "", .choices = {},
     .surfaces = kToml | kWire, .help = "Keep cluster ids stable across the stream's frames"},
    {.name = "sticky_rings", .toml = nullptr, .python = nullptr, .group = G::kCluster, .kind = K::kUint,
     .get = get_member<&P::clustering, &C::sticky_rings>, .set = set_member<&P::clustering, &C::sticky_rings>,
     .lo = 0, .hi = 64, .lo_open = false, .zero = "none", .unit = "", .choices = {},
     .surfaces = kToml | kWire,
     .help = "Edge rings a cluster border may move back to the previous frame's; 0 = none"},
};
// clang-format on
// ClusterParams::keep_links has no row: it asks the engine for an extra output (the link
// forest, for tests and cluster control), it is no setting of the result.

// "-1", "0.25" and "10000" rather than std::to_string's "-1.000000".
std::string show(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

std::string lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) { return std::tolower(c); });
  return out;
}

// Whole-string number: "2.5x" or "" is an error, not 2.5 or 0.
bool parse_number(std::string_view text, double& out) {
  const std::string s(text);
  if (s.empty()) return false;
  char* end = nullptr;
  out = std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size() && std::isfinite(out);
}

}  // namespace

std::string ParamRow::flag() const {
  std::string out = std::string("--") + name;
  std::replace(out.begin(), out.end(), '_', '-');
  return out;
}

std::span<const ParamRow> param_table() { return kRows; }

const ParamRow* find_param(std::string_view name) {
  for (const ParamRow& row : kRows)
    if (name == row.name) return &row;
  return nullptr;
}

bool same_params(const Params& a, const Params& b) {
  return std::ranges::all_of(param_table(), [&](const ParamRow& row) { return row.get(a) == row.get(b); });
}

std::string format_param(const ParamRow& row, double value) {
  switch (row.kind) {
    case ParamKind::kBool:
      return value != 0.0 ? "true" : "false";
    case ParamKind::kUint:
      return std::to_string(static_cast<uint64_t>(value));
    case ParamKind::kEnum:
      for (const ParamChoice& c : row.choices)
        if (c.value == static_cast<int>(value)) return c.name;
      return "?";
    case ParamKind::kFloat:
      break;
  }
  // The shortest text that reads back as the same float: 0.7, not 0.699999988.
  char text[32];
  const auto end = std::to_chars(text, text + sizeof text, static_cast<float>(value)).ptr;
  return std::string(text, end);
}

Status parse_param(const ParamRow& row, std::string_view text, double& out) {
  const std::string given = row.kind == ParamKind::kEnum ? std::string(text) : lower(text);
  const std::string quoted = " (got \"" + std::string(text) + "\")";
  switch (row.kind) {
    case ParamKind::kBool:
      if (given == "true" || given == "1" || given == "on" || given == "yes") return out = 1.0, Status{};
      if (given == "false" || given == "0" || given == "off" || given == "no") return out = 0.0, Status{};
      return invalid_argument(std::string(row.name) + " must be true or false" + quoted);
    case ParamKind::kEnum:
      for (const ParamChoice& c : row.choices)
        if (given == c.name) return out = c.value, Status{};
      return invalid_argument(std::string(row.name) + " must be one of " + choice_names(row, ", ") + quoted);
    case ParamKind::kUint:
      if (!parse_number(given, out) || out != std::floor(out) || out < 0 || out > 4294967295.0)
        return invalid_argument(std::string(row.name) + " must be a whole number" + quoted);
      return {};
    case ParamKind::kFloat:
      if (!parse_number(given, out))
        return invalid_argument(std::string(row.name) + " must be a number" + quoted);
      return {};
  }
  return {};
}

Status check_param(const ParamRow& row, double v) {
  if (row.kind != ParamKind::kFloat && row.kind != ParamKind::kUint) return {};
  const std::string name = row.name, got = " (got " + show(v) + ")";
  if (std::isnan(v)) return invalid_argument(name + " is NaN");
  if (row.zero && v == 0.0) return {};
  const bool below = row.lo_open ? !(v > row.lo) : !(v >= row.lo);
  const bool above = !(v <= row.hi);
  if (!below && !above) return {};
  const std::string zero = row.zero ? std::string("0 = ") + row.zero : "";
  if (row.lo_open && below)
    return invalid_argument(name + " must be > " + show(row.lo) +
                            (zero.empty() ? "" : " or 0 (" + zero + ")") + got);
  if (row.lo_open || row.kind == ParamKind::kUint)
    return invalid_argument(name + " must be at most " + show(row.hi) + row.unit + got);
  return invalid_argument(name + " must be in [" + show(row.lo) + ", " + show(row.hi) + "]" + row.unit +
                          (zero.empty() ? got : " (" + zero + "; got " + show(v) + ")"));
}

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

std::string choice_names(std::span<const ParamChoice> choices, std::string_view separator, bool quoted) {
  std::vector<std::string> names;
  for (const ParamChoice& c : choices) names.emplace_back(c.name);
  return join_names(names, separator, quoted);
}

std::string choice_names(const ParamRow& row, std::string_view separator, bool quoted) {
  return choice_names(row.choices, separator, quoted);
}

std::optional<int> choice_wire(std::span<const ParamChoice> choices, int value) {
  for (const ParamChoice& c : choices)
    if (c.value == value) return c.wire;
  return std::nullopt;
}

std::optional<int> choice_value(std::span<const ParamChoice> choices, int wire) {
  for (const ParamChoice& c : choices)
    if (c.wire == wire) return c.value;
  return std::nullopt;
}

std::optional<int> choice_wire(const ParamRow& row, int value) { return choice_wire(row.choices, value); }
std::optional<int> choice_value(const ParamRow& row, int wire) { return choice_value(row.choices, wire); }

Status validate(const Params& p) {
  if (!p.filter && !p.cluster) return invalid_argument("nothing to compute: enable filter and/or cluster");
  for (const ParamRow& row : kRows) {
    if (row.group == ParamGroup::kCluster && !p.cluster) continue;
    FQ_RETURN_IF_ERROR(check_param(row, row.get(p)));
  }
  return {};
}

}  // namespace fq
