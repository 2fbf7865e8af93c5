#include "python/keywords.h"

#include <pybind11/stl.h>

#include <charconv>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace fq::py {

namespace {

namespace pyb = pybind11;

/// The table's surface bit of a function's keywords.
ParamSurface surface_of(const std::string& function) {
  if (function == "filter") return kPythonFilter;
  if (function == "cluster") return kPythonCluster;
  throw pyb::value_error("no keywords for '" + function + "'");
}

/// The shortest decimal that reads back as `v` in float32: what the C++ source says.
double as_written(double v) {
  char text[32];
  const auto end = std::to_chars(text, text + sizeof text, static_cast<float>(v)).ptr;
  return std::stod(std::string(text, end));
}

pyb::object python_value(const ParamRow& row, double v) {
  switch (row.kind) {
    case ParamKind::kFloat:
      return pyb::float_(as_written(v));
    case ParamKind::kBool:
      return pyb::bool_(v != 0.0);
    case ParamKind::kUint:
      return pyb::int_(static_cast<uint32_t>(v));
    case ParamKind::kEnum:
      return pyb::str(format_param(row, v));
  }
  return pyb::none();
}

const char* type_name(ParamKind kind) {
  switch (kind) {
    case ParamKind::kFloat:
      return "float";
    case ParamKind::kBool:
      return "bool";
    case ParamKind::kUint:
      return "int";
    case ParamKind::kEnum:
      return "str";
  }
  return "";
}

pyb::object choices_of(const ParamRow& row) {
  if (row.kind != ParamKind::kEnum) return pyb::none();
  pyb::list names;
  for (const ParamChoice& c : row.choices) names.append(c.name);
  return std::move(names);
}

/// The table's help as a sentence for a docstring.
std::string sentence(const char* help) {
  std::string out = help;
  if (!out.empty() && out.back() != '.') out += '.';
  return out;
}

[[noreturn]] void type_error(const char* name, const char* expected, const pyb::handle& value) {
  throw pyb::type_error(std::string(name) + " must be " + expected + ", got " +
                        std::string(pyb::str(pyb::type::handle_of(value).attr("__name__"))));
}

bool is_bool(const pyb::handle& v) {
  return pyb::isinstance<pyb::bool_>(v) ||
         std::string(pyb::str(pyb::type::handle_of(v).attr("__name__"))) == "bool_";
}

/// `v` as the row's Params value: TypeError for a value of the wrong type, ValueError for a
/// name not among the choices or a negative count.
double value_of(const ParamRow& row, const char* name, const pyb::handle& v) {
  switch (row.kind) {
    case ParamKind::kFloat:
      if (is_bool(v) || pyb::isinstance<pyb::str>(v) || !PyNumber_Check(v.ptr()))
        type_error(name, "a number", v);
      return static_cast<float>(pyb::cast<double>(v));
    case ParamKind::kBool:
      if (!is_bool(v)) type_error(name, "True or False", v);
      return pyb::cast<bool>(v) ? 1.0 : 0.0;
    case ParamKind::kUint: {
      if (is_bool(v) || !PyIndex_Check(v.ptr())) type_error(name, "an integer", v);
      const auto n = pyb::cast<long long>(pyb::reinterpret_steal<pyb::object>(PyNumber_Index(v.ptr())));
      if (n < 0 || n > std::numeric_limits<uint32_t>::max())
        throw pyb::value_error(std::string(name) + " must be in [0, 2^32 - 1] (got " + std::to_string(n) +
                               ")");
      return static_cast<double>(n);
    }
    case ParamKind::kEnum: {
      if (!pyb::isinstance<pyb::str>(v)) type_error(name, "a string", v);
      const std::string given = pyb::cast<std::string>(v);
      double out = 0;
      if (!parse_param(row, given, out).ok())
        throw pyb::value_error(std::string(name) + " must be " + choice_names(row, " or ", true) + ", got '" +
                               given + "'");
      return out;
    }
  }
  return 0.0;
}

}  // namespace

pyb::list keyword_rows(const std::string& function) {
  const ParamSurface surface = surface_of(function);
  const Params defaults;
  pyb::list out;
  for (const ParamRow& row : param_table())
    if (row.on(surface))
      out.append(pyb::make_tuple(row.python_keyword(), type_name(row.kind),
                                 python_value(row, row.get(defaults)), choices_of(row), sentence(row.help)));
  return out;
}

void apply_keywords(const std::string& function, const pyb::dict& keywords, Params& params) {
  const ParamSurface surface = surface_of(function);
  for (const auto& [key, value] : keywords) {
    const std::string name = pyb::cast<std::string>(key);
    const ParamRow* found = nullptr;
    for (const ParamRow& row : param_table())
      if (row.on(surface) && name == row.python_keyword()) found = &row;
    if (!found)
      throw pyb::type_error(
          std::string(function).append("() got an unexpected keyword argument '").append(name).append("'"));
    found->set(params, value_of(*found, name.c_str(), value));
  }
}

pyb::list param_rows() {
  constexpr std::pair<ParamSurface, const char*> kSurfaces[] = {
      {kFqfilter, "fqfilter"},     {kToml, "toml"},           {kWire, "wire"},    {kPythonFilter, "filter"},
      {kPythonCluster, "cluster"}, {kPythonStream, "Stream"}, {kReport, "report"}};
  pyb::list out;
  for (const ParamRow& row : param_table()) {
    pyb::list surfaces;
    for (const auto& [bit, name] : kSurfaces)
      if (row.on(bit)) surfaces.append(name);
    out.append(pyb::make_tuple(row.name, row.python_keyword(), surfaces));
  }
  return out;
}

}  // namespace fq::py
