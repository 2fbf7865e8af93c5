#include "daemon/config/stream_settings.h"

#include <optional>

#include "daemon/config/stream_setting_table.h"
#include "wire/header_codec.h"

namespace fq::daemon {

namespace {

// The first choice (ResultForm's 0) when `f` is none of them.
const ParamChoice& choice_of(ResultForm f) {
  for (const ParamChoice& c : kResultForms)
    if (c.value == static_cast<int>(f)) return c;
  return kResultForms[0];
}

}  // namespace

bool parse_compute(const std::string& s, Params& inout) {
  const std::optional<wire::Compute> c = wire::compute_from_name(s);
  return c && wire::apply_compute(*c, inout).ok();
}

const char* compute_name(const Params& p) { return wire::compute_name(wire::compute_of(p)); }

bool parse_result_form(const std::string& s, ResultForm& out) {
  for (const ParamChoice& c : kResultForms)
    if (s == c.name) {
      out = static_cast<ResultForm>(c.value);
      return true;
    }
  return false;
}

const char* result_form_name(ResultForm f) { return choice_of(f).name; }
wire::ResultForm to_wire(ResultForm f) { return static_cast<wire::ResultForm>(choice_of(f).wire); }
ResultForm from_wire(wire::ResultForm f) {
  return static_cast<ResultForm>(choice_value(kResultForms, f).value_or(kResultForms[0].value));
}

Status validate(const StreamSettings& s) {
  // The clustering parameters are checked even when the stream only filters: a frame or a
  // control request may switch clustering on at any time.
  Params all = s.params;
  all.filter = all.cluster = true;
  FQ_RETURN_IF_ERROR(fq::validate(all));
  for (const StreamSettingRow& row : stream_setting_table())
    FQ_RETURN_IF_ERROR(check_setting(row, row.get(s)));
  return {};
}

}  // namespace fq::daemon
