#include "core/params.h"

#include <string>

#include "core/param_table.h"

namespace fq {

namespace {

// The names live in the parameter table's enum rows (core/param_table.cpp), with their wire numbers.
const ParamRow& row_of(FilterMethod) { return *find_param("mode"); }
const ParamRow& row_of(ClusterMethod) { return *find_param("cluster_method"); }
const ParamRow& row_of(ClusterGeometry) { return *find_param("cluster_geometry"); }

template <typename Enum>
const char* name_of(Enum e, const char* otherwise) {
  for (const ParamChoice& c : row_of(Enum{}).choices)
    if (c.value == static_cast<int>(e)) return c.name;
  return otherwise;
}

// Case-sensitive, as configs and command lines spell the names.
template <typename Enum>
std::optional<Enum> parse_name(std::string_view name) {
  for (const ParamChoice& c : row_of(Enum{}).choices)
    if (name == c.name) return static_cast<Enum>(c.value);
  return std::nullopt;
}

template <typename Enum>
std::vector<std::string> names_of() {
  std::vector<std::string> out;
  for (const ParamChoice& c : row_of(Enum{}).choices) out.emplace_back(c.name);
  return out;
}

}  // namespace

const char* filter_method_name(FilterMethod m) { return method_name(m); }

bool parse_filter_method(const std::string& s, FilterMethod& out) {
  const std::optional<FilterMethod> m = parse_method<FilterMethod>(s);
  if (m) out = *m;
  return m.has_value();
}

bool parse_cluster_geometry(const std::string& s, ClusterGeometry& out) {
  const std::optional<ClusterGeometry> g = parse_name<ClusterGeometry>(s);
  if (g) out = *g;
  return g.has_value();
}

const char* cluster_geometry_name(ClusterGeometry g) { return name_of(g, "auto"); }

std::vector<std::string> cluster_geometry_names() { return names_of<ClusterGeometry>(); }

const char* method_name(FilterMethod m) { return name_of(m, "?"); }
const char* method_name(ClusterMethod m) { return name_of(m, "?"); }

template <typename Method>
std::optional<Method> parse_method(std::string_view name) {
  return parse_name<Method>(name);
}
template std::optional<FilterMethod> parse_method<FilterMethod>(std::string_view);
template std::optional<ClusterMethod> parse_method<ClusterMethod>(std::string_view);

template <typename Method>
std::vector<std::string> method_names() {
  return names_of<Method>();
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
