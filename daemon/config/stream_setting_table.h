// The one table of a stream's settings beside its parameters (the latency budget and the
// output encoding): a row per setting with the name every surface spells it by, where the
// config file holds it, its kind, range and help. The config reader, validate(), the control
// socket's SetParams and ControlReply (fields found by the row's name through protobuf
// reflection) and the settings audit walk this table, so a setting is added here once
// (docs/ARCHITECTURE.md, "Adding a stream setting"). The parameters have their own table,
// core/param_table.h; the compute mode is one of its views (Params::filter / ::cluster).
#pragma once

#include <span>
#include <string>
#include <string_view>

#include "common/status.h"
#include "daemon/config/stream_settings.h"
#include "wire/fq.pb.h"

namespace fq::daemon {

class TomlReader;

/// How a setting's value is held and spelled. Every value passes through a double, which
/// holds each kind exactly.
enum class SettingKind {
  kDouble,  ///< a number: TOML float or integer, wire double
  kInt,     ///< an integer: TOML integer, wire uint32
  kUint,    ///< an unsigned integer: TOML integer (or the `zero` word), wire uint32
  kEnum,    ///< one of `choices`: TOML string, wire enum
};

struct StreamSettingRow {
  const char* name;   ///< TOML key, SetParams and ControlReply field, audit key, fqctl key
  const char* table;  ///< TOML sub-table holding the key ("output"), or null: the stream's own table
  SettingKind kind;
  double (*get)(const StreamSettings&);
  void (*set)(StreamSettings&, double);
  double lo, hi;                         ///< range, both ends inclusive (not kEnum)
  const char* zero;                      ///< non-null: 0 is also allowed, written as this word ("same")
  std::span<const ParamChoice> choices;  ///< kEnum: its names, native values and wire numbers
  const char* help;

  /// The dotted name in a stream's table: the name, after its sub-table's and a dot if it has one.
  std::string key() const;
};

/// Every row, in the order of the audit and of ControlReply.
std::span<const StreamSettingRow> stream_setting_table();

/// The value's text as a config spells it ("100", "same", "mesh").
std::string format_setting(const StreamSettingRow& row, double value);
/// Range check of one value: "output.chunks must be in [1, 256] (got 300)".
Status check_setting(const StreamSettingRow& row, double value);

/// Reads the rows of TOML table `table` (null: the stream's own) from `r` into `s`; the
/// reader records a bad value.
void read_settings(TomlReader& r, const char* table, StreamSettings& s);

/// The settings SetParams carries into `s`, each only when given (validate(s) checks them).
void settings_from_wire(const wire::SetParams& q, StreamSettings& s);
/// Every setting of `s` into the reply of get_params / set_params.
void settings_to_wire(const StreamSettings& s, wire::ControlReply& r);

}  // namespace fq::daemon
