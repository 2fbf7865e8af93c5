#include "python/keywords.h"

#include <pybind11/stl.h>

#include <charconv>
#include <cstdint>
#include <limits>
#include <string>
#include <variant>
#include <vector>

namespace fq::py {

namespace {

namespace pyb = pybind11;

template <class P>
using Member = std::variant<float P::*, bool P::*, uint32_t P::*, FilterMethod P::*, ClusterMethod P::*,
                            ClusterGeometry P::*>;

/// One keyword: `name` sets `member` of P.
template <class P>
struct Row {
  const char* name;
  Member<P> member;
  const char* help;
};

// clang-format off
const Row<FilterParams> kFilterRows[] = {
    {"mode", &FilterParams::method,
     "'qf+' (fq's filter, its strength derived from the noise it estimates), 'qf' (the paper's "
     "filtered quadrics exactly) or 'bf' (bilateral baseline)."},
    {"sigma_s", &FilterParams::sigma_s, "qf and bf: spatial extent of the diffusion, in mean edge lengths."},
    {"sigma_r", &FilterParams::sigma_r, "qf: range extent (RMS quadric distance), in mean edge lengths."},
    {"sigma_b", &FilterParams::sigma_b, "Finest detail captured by the neighbourhood quadrics; 0 means sigma_s / 2."},
    {"sigma_n", &FilterParams::sigma_n, "Normal smoothing of the constrained update; 0 means sigma_s / 2."},
    {"constrained", &FilterParams::constrained, "Move vertices along the smoothed normal only."},
    {"tikhonov", &FilterParams::tikhonov, "Pull toward the current position, relative to tr(A)/3; 0 is the paper's solver."},
};
// "qf+": the noise it filters for.
const Row<RefineParams> kRefineRows[] = {
    {"known_noise", &RefineParams::known_noise,
     "qf+: noise to filter for, in mean edge lengths (along the normal); 0 estimates it per mesh."},
    {"strength", &RefineParams::strength,
     "qf+: multiplies the noise the filter's strengths come from (2: as for twice the noise; 0: no filtering)."},
};
// The filter's quadric field is what the clustering scores and links with.
const Row<FilterParams> kClusterFilterRows[] = {
    {"sigma_s", &FilterParams::sigma_s, "Spatial extent of the quadric diffusion, in mean edge lengths."},
    {"sigma_r", &FilterParams::sigma_r, "Range extent of the quadric diffusion, in mean edge lengths."},
    {"sigma_b", &FilterParams::sigma_b, "Finest detail captured by the neighbourhood quadrics; 0 means sigma_s / 2."},
};
const Row<ClusterParams> kClusterRows[] = {
    {"method", &ClusterParams::method, "'quadric' (the paper) or 'euclidean' (plain quick shift)."},
    {"sigma_d", &ClusterParams::sigma_d, "Spatial extent of score and proximity, in mean edge lengths."},
    {"sigma_q", &ClusterParams::sigma_q, "Range extent of the clustering (RMS quadric distance)."},
    {"theta", &ClusterParams::theta, "In (0, 1]; higher gives fewer, larger clusters."},
    {"target_clusters", &ClusterParams::target_clusters,
     "Choose theta per mesh to give about this many clusters; 0 uses theta."},
    {"min_cluster_size", &ClusterParams::min_cluster_size,
     "Split clusters into mesh-connected parts and merge parts under this many vertices; 0 is off."},
    {"geometry", &ClusterParams::geometry,
     "Quadrics the clustering uses: 'input' (the paper), 'filtered' (after a constrained filter) "
     "or 'auto' (filtered with a target_clusters)."},
};
// clang-format on

std::vector<std::string> choices(FilterMethod) { return method_names<FilterMethod>(); }
std::vector<std::string> choices(ClusterMethod) { return method_names<ClusterMethod>(); }
std::vector<std::string> choices(ClusterGeometry) { return cluster_geometry_names(); }
const char* name_of(FilterMethod m) { return method_name(m); }
const char* name_of(ClusterMethod m) { return method_name(m); }
const char* name_of(ClusterGeometry g) { return cluster_geometry_name(g); }

/// The shortest decimal that reads back as `v` in float32: what the C++ source says.
double as_written(float v) {
  char text[32];
  const auto end = std::to_chars(text, text + sizeof text, v).ptr;
  return std::stod(std::string(text, end));
}

pyb::object python_default(float v) { return pyb::float_(as_written(v)); }
pyb::object python_default(bool v) { return pyb::bool_(v); }
pyb::object python_default(uint32_t v) { return pyb::int_(v); }
template <class Enum>
pyb::object python_default(Enum v) {
  return pyb::str(name_of(v));
}

const char* type_name(float) { return "float"; }
const char* type_name(bool) { return "bool"; }
const char* type_name(uint32_t) { return "int"; }
template <class Enum>
const char* type_name(Enum) {
  return "str";
}

pyb::object choices_of(float) { return pyb::none(); }
pyb::object choices_of(bool) { return pyb::none(); }
pyb::object choices_of(uint32_t) { return pyb::none(); }
template <class Enum>
pyb::object choices_of(Enum e) {
  return pyb::cast(choices(e));
}

template <class P, std::size_t N>
void add_rows(pyb::list& out, const Row<P> (&rows)[N]) {
  const P defaults{};
  for (const Row<P>& row : rows) {
    std::visit(
        [&](auto member) {
          const auto value = defaults.*member;
          out.append(pyb::make_tuple(row.name, type_name(value), python_default(value), choices_of(value), row.help));
        },
        row.member);
  }
}

[[noreturn]] void type_error(const char* name, const char* expected, const pyb::handle& value) {
  throw pyb::type_error(std::string(name) + " must be " + expected + ", got " +
                        std::string(pyb::str(pyb::type::handle_of(value).attr("__name__"))));
}

bool is_bool(const pyb::handle& v) {
  return pyb::isinstance<pyb::bool_>(v) || std::string(pyb::str(pyb::type::handle_of(v).attr("__name__"))) == "bool_";
}

void set(const char* name, const pyb::handle& v, float& out) {
  if (is_bool(v) || pyb::isinstance<pyb::str>(v) || !PyNumber_Check(v.ptr())) type_error(name, "a number", v);
  out = static_cast<float>(pyb::cast<double>(v));
}

void set(const char* name, const pyb::handle& v, bool& out) {
  if (!is_bool(v)) type_error(name, "True or False", v);
  out = pyb::cast<bool>(v);
}

void set(const char* name, const pyb::handle& v, uint32_t& out) {
  if (is_bool(v) || !PyIndex_Check(v.ptr())) type_error(name, "an integer", v);
  const auto n = pyb::cast<long long>(pyb::reinterpret_steal<pyb::object>(PyNumber_Index(v.ptr())));
  if (n < 0 || n > std::numeric_limits<uint32_t>::max())
    throw pyb::value_error(std::string(name) + " must be in [0, 2^32 - 1] (got " + std::to_string(n) + ")");
  out = static_cast<uint32_t>(n);
}

template <class Enum>
void set(const char* name, const pyb::handle& v, Enum& out) {
  if (!pyb::isinstance<pyb::str>(v)) type_error(name, "a string", v);
  const std::string given = pyb::cast<std::string>(v);
  for (const std::string& choice : choices(out)) {
    if (choice != given) continue;
    if constexpr (std::is_same_v<Enum, ClusterGeometry>)
      parse_cluster_geometry(given, out);
    else
      out = *parse_method<Enum>(given);
    return;
  }
  throw pyb::value_error(std::string(name) + " must be " + join_names(choices(out), " or ", true) + ", got '" +
                         given + "'");
}

/// Sets `p`'s member named `name` when one of `rows` has that name; false when none has.
template <class P, std::size_t N>
bool set_by_name(const Row<P> (&rows)[N], const std::string& name, const pyb::handle& value, P& p) {
  for (const Row<P>& row : rows) {
    if (name != row.name) continue;
    std::visit([&](auto member) { set(row.name, value, p.*member); }, row.member);
    return true;
  }
  return false;
}

}  // namespace

pyb::list keyword_rows(const std::string& function) {
  pyb::list out;
  if (function == "filter") {
    add_rows(out, kFilterRows);
    add_rows(out, kRefineRows);
  } else if (function == "cluster") {
    add_rows(out, kClusterRows);
    add_rows(out, kClusterFilterRows);
  } else {
    throw pyb::value_error("no keywords for '" + function + "'");
  }
  return out;
}

void apply_keywords(const std::string& function, const pyb::dict& keywords, Params& params) {
  for (const auto& [key, value] : keywords) {
    const std::string name = pyb::cast<std::string>(key);
    const bool known = function == "filter"
                           ? set_by_name(kFilterRows, name, value, params.filtering) ||
                                 set_by_name(kRefineRows, name, value, params.filtering.refine)
                           : set_by_name(kClusterRows, name, value, params.clustering) ||
                                 set_by_name(kClusterFilterRows, name, value, params.filtering);
    if (!known) throw pyb::type_error(std::string(function).append("() got an unexpected keyword argument '").append(name).append("'"));
  }
}

}  // namespace fq::py
