#include "clients/fqfilter/param_options.h"

#include <cstdint>
#include <string>
#include <vector>

namespace fq::cli {

void add_param_options(CLI::App& app, Params& p, ParamGroup group) {
  for (const ParamRow& row : param_table()) {
    if (!row.on(kFqfilter) || row.group != group) continue;
    const ParamRow* r = &row;
    const std::string flag = row.flag(), shown = format_param(row, row.get(p));
    switch (row.kind) {
      case ParamKind::kBool:
        app.add_flag_function(
            flag, [&p, r](std::int64_t count) { r->set(p, count > 0 ? 1.0 : 0.0); }, row.help);
        break;
      case ParamKind::kFloat:
        app.add_option_function<float>(
               flag, [&p, r](float v) { r->set(p, v); }, row.help)
            ->default_str(shown)
            ->check(CLI::Range(row.lo, row.hi));
        break;
      case ParamKind::kUint:
        app.add_option_function<uint32_t>(
               flag, [&p, r](uint32_t v) { r->set(p, v); }, row.help)
            ->default_str(shown)
            ->check(CLI::Range(row.lo, row.hi));
        break;
      case ParamKind::kEnum: {
        std::vector<std::string> names;
        for (const ParamChoice& c : row.choices) names.emplace_back(c.name);
        app.add_option_function<std::string>(
               flag,
               [&p, r](const std::string& name) {
                 if (double v = 0; parse_param(*r, name, v).ok()) r->set(p, v);  // IsMember has checked it
               },
               row.help)
            ->default_str(shown)
            ->check(CLI::IsMember(names));
        break;
      }
    }
  }
}

}  // namespace fq::cli
