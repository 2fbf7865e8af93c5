#include "clients/common/override_options.h"

#include <optional>

#include "wire/header_codec.h"

namespace fq::client {

void add_override_options(CLI::App& app, OverrideArgs& a) {
  const std::string g = "Parameter overrides (sigmas in mean edge lengths; unset = the stream's)";
  for (const ParamRow& row : param_table()) {
    if (!row.on(kWire)) continue;
    const ParamRow* r = &row;
    std::string help = row.help;
    if (row.kind == ParamKind::kBool) help += " (true/false)";
    app.add_option_function<std::string>(
           row.flag(), [&a, r](const std::string& v) { a.given.emplace_back(r, v); }, help)
        ->group(g);
  }
  app.add_option("--compute", a.compute, "filter | cluster | filter_and_cluster")->group(g);
}

Status to_wire(const OverrideArgs& a, wire::ParamOverrides& o, wire::Compute& compute) {
  o.Clear();
  for (const auto& [row, text] : a.given) {
    double v = 0;
    if (Status s = parse_param(*row, text, v); !s.ok())
      return invalid_argument(row->flag() + ": " + s.message());
    wire::set_wire_value(*row, v, o);
  }
  compute = wire::COMPUTE_DEFAULT;
  if (!a.compute.empty()) {
    const std::optional<wire::Compute> c = wire::compute_from_name(a.compute);
    if (!c)
      return invalid_argument("--compute must be filter, cluster or filter_and_cluster (got " + a.compute +
                              ")");
    compute = *c;
  }
  return {};
}

}  // namespace fq::client
