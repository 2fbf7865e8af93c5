// The one table of fq's parameters: a row per member of fq::Params that a user sets (the
// filter, "qf+"'s noise, the temporal strength, the clustering, and the filter/cluster
// switches), with the name every surface spells it by, its kind, range, "0 = derived" rule,
// help and the surfaces that show it. validate(Params), fqfilter's options, the override
// options of fqpub/fqstreambench, fqd's TOML, the wire (by field name), fqctl and the Python
// keywords all walk this table, so a parameter is added here once (docs/ARCHITECTURE.md,
// "Adding a parameter").
//
// Hand-written, not generated: it is about 20 rows of data that read as a specification,
// its accessors are checked by the compiler against fq::Params, and fq.proto is checked
// against it by a test (tests/wire/param_table_wire_test.cpp); a generator would add a build
// step and a second language for less text than it replaces.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "common/status.h"
#include "core/params.h"

namespace fq {

enum class ParamKind { kFloat, kUint, kBool, kEnum };

/// Where a row's parameter appears. fqctl shows every kWire row (it speaks the wire).
enum ParamSurface : unsigned {
  kFqfilter = 1u << 0,       ///< fqfilter --NAME-WITH-DASHES
  kToml = 1u << 1,           ///< fqd's [defaults.filter|cluster] and [streams.ID.filter|cluster]
  kWire = 1u << 2,           ///< ParamOverrides.NAME (frame headers, SetParams, fqctl, fqpub)
  kPythonFilter = 1u << 3,   ///< keyword of fq.filter
  kPythonCluster = 1u << 4,  ///< keyword of fq.cluster
  kPythonStream = 1u << 5,   ///< argument of fq.Stream
  kReport = 1u << 6,         ///< fqfilter --json's "params"
};

/// The group a row belongs to: its TOML table ([filter] or [cluster]), fqfilter's help group,
/// and whether validate checks it when clustering is off (kCluster rows are checked only
/// with Params::cluster).
enum class ParamGroup { kCompute, kFilter, kNoise, kTemporal, kCluster };

/// One name of an enum row: the native value (as int) and its number on the wire.
struct ParamChoice {
  const char* name;
  int value;
  int wire;
};

/// Every value passes through a double: float, uint32 and enum (as int) round-trip exactly.
struct ParamRow {
  const char* name;  ///< ParamOverrides field, fqctl key, Python keyword, fqfilter --flag ('_' -> '-')
  const char* toml;  ///< key in its TOML table when it differs from name ([filter] method = "qf+"), else null
  const char* python;  ///< Python keyword when it differs from name (fq.cluster(method=...)), else null
  ParamGroup group;
  ParamKind kind;
  double (*get)(const Params&);
  void (*set)(Params&, double);
  double lo, hi;     ///< range, both ends inclusive (kFloat, kUint)
  bool lo_open;      ///< the range is (lo, hi]
  const char* zero;  ///< non-null: 0 is also allowed and means this ("sigma_s / 2", "estimated per frame")
  const char* unit;  ///< " mean edge lengths" or ""
  std::span<const ParamChoice> choices;  ///< kEnum: its names, in help order
  unsigned surfaces;                     ///< ParamSurface bits
  const char* help;
  /// What the parameter resolves to (sigma_b's 0 -> sigma_s / 2): the report shows it; null: get.
  double (*effective)(const Params&) = nullptr;

  bool on(ParamSurface s) const { return (surfaces & s) != 0; }
  /// The TOML key and the Python keyword.
  const char* toml_key() const { return toml ? toml : name; }
  const char* python_keyword() const { return python ? python : name; }
  /// "--sigma-s": the command-line flag of fqfilter, fqpub and fqstreambench.
  std::string flag() const;
};

/// Every row, in help order (filter, noise, temporal, clustering).
std::span<const ParamRow> param_table();
/// The row named `name` (ParamRow::name), or null.
const ParamRow* find_param(std::string_view name);

/// Whether every row reads the same value from `a` and `b`: the same settings, as every
/// surface sees them.
bool same_params(const Params& a, const Params& b);

/// The value's text in the names every surface uses: "qf+", "true", "0.7", "12".
std::string format_param(const ParamRow& row, double value);
/// Parses a value given as text (fqctl, fqpub, TOML strings): numbers whole-string, booleans
/// true/false/1/0/on/off/yes/no in any case, enums by their names exactly ("qf+", "auto").
/// kInvalidArgument naming the row and, for an enum, its names.
Status parse_param(const ParamRow& row, std::string_view text, double& out);
/// Range check of one value; the message names the row, its range and its "0 =" rule.
Status check_param(const ParamRow& row, double value);
/// "qf or bf" for messages; `quoted`: "\"qf\" or \"bf\""; `separator` " | " for help texts.
std::string join_names(const std::vector<std::string>& names, std::string_view separator = " or ",
                       bool quoted = false);
/// The names of an enum row joined by `separator` ("qf+ or qf or bf"), quoted if asked.
std::string choice_names(std::span<const ParamChoice> choices, std::string_view separator = " or ",
                         bool quoted = false);
std::string choice_names(const ParamRow& row, std::string_view separator = " or ", bool quoted = false);
/// The wire number of an enum's native value and back; nullopt outside the choices.
std::optional<int> choice_wire(std::span<const ParamChoice> choices, int value);
std::optional<int> choice_value(std::span<const ParamChoice> choices, int wire);
std::optional<int> choice_wire(const ParamRow& row, int value);
std::optional<int> choice_value(const ParamRow& row, int wire);

}  // namespace fq
