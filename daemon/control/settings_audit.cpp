#include "daemon/control/settings_audit.h"

#include <spdlog/spdlog.h>

#include "core/param_table.h"
#include "daemon/config/stream_setting_table.h"
#include "daemon/stream/stream_admission.h"

namespace fq::daemon {
namespace {

// The parameters by the table's wire rows (core/param_table.h), so that the keys are the ones
// fqctl sets, the values are spelled as configs spell them ("qf+", "auto"), and a row added
// to the table is audited without a change here.
void param_fields(const Params& p, std::vector<std::pair<std::string, std::string>>& out) {
  for (const ParamRow& row : param_table())
    if (row.on(kWire)) out.emplace_back(row.name, format_param(row, row.get(p)));
}

}  // namespace

std::vector<std::pair<std::string, std::string>> settings_fields(const StreamSettings& s) {
  std::vector<std::pair<std::string, std::string>> out;
  out.emplace_back("compute", compute_name(s.params));
  param_fields(s.params, out);
  for (const StreamSettingRow& row : stream_setting_table())
    out.emplace_back(row.name, format_setting(row, row.get(s)));
  return out;
}

std::vector<std::string> settings_changes(const StreamSettings& before, const StreamSettings& after) {
  const auto a = settings_fields(before), b = settings_fields(after);
  std::vector<std::string> out;
  for (size_t i = 0; i < a.size() && i < b.size(); ++i)
    if (a[i].second != b[i].second) out.push_back(a[i].first + " " + a[i].second + " -> " + b[i].second);
  return out;
}

void log_settings_changes(const std::string& stream_id, const StreamSettings& before,
                          const StreamSettings& after, const char* cause, LogLimiter* limiter) {
  const std::vector<std::string> changes = settings_changes(before, after);
  uint64_t held_back = 0;
  if (changes.empty() || !spdlog::should_log(spdlog::level::info)) return;
  if (limiter && !limiter->allow_now(held_back)) return;
  const std::string id = printable_id(stream_id);
  for (const std::string& change : changes) spdlog::info("{} {} ({})", id, change, cause);
  if (held_back > 0)
    spdlog::info("({} earlier {} changes not logged: over the log rate limit)", held_back, cause);
}

}  // namespace fq::daemon
