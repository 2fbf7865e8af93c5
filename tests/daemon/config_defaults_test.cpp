// The defaults that configs/fqd.toml, docs/DAEMON.md's table of configuration keys and
// docs/FQFILTER.md's table of options show are the built-in ones. Each value shown is read by
// fqd's own parser (the parameter table's rows for [defaults.filter] and [defaults.cluster]) and
// must give the configuration an empty file gives, and each fqfilter option of the parameter
// table must show its row's default; so a changed default fails here until the docs follow.
// A value of configs/fqd.toml that is meant to differ says "not the default" on its line.
#include <gtest/gtest.h>
#include <toml++/toml.h>

#include <algorithm>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "core/param_table.h"
#include "core/params.h"
#include "daemon/config/config.h"

namespace fq::daemon {
namespace {

std::string source_file(const std::string& relative) {
  std::ifstream in(std::string(FQ_SOURCE_DIR) + "/" + relative, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

/// TOML text that sets only `key` (dotted) to `value`.
std::string toml_setting(const std::string& key, const toml::node& value) {
  toml::table root;
  toml::table* table = &root;
  size_t start = 0;
  for (size_t dot = key.find('.'); dot != std::string::npos; start = dot + 1, dot = key.find('.', start))
    table = table->emplace<toml::table>(key.substr(start, dot - start)).first->second.as_table();
  value.visit([&](const auto& v) { table->insert_or_assign(key.substr(start), v); });
  std::ostringstream text;
  text << root;
  return text.str();
}

/// Whether `key = value` alone gives the configuration of an empty file.
testing::AssertionResult is_builtin_default(const std::string& key, const toml::node& value,
                                            const std::string& where) {
  const std::string text = toml_setting(key, value);
  DaemonConfig shown, builtin;
  if (Status s = parse_config(text, where, shown); !s.ok()) return testing::AssertionFailure() << s.message();
  EXPECT_TRUE(parse_config("", where, builtin).ok());
  shown.lines = builtin.lines;  // where each key was read, not what it holds
  if (shown == builtin) return testing::AssertionSuccess();
  return testing::AssertionFailure() << where << ": " << text << " -- not fqd's built-in default";
}

/// A value as the docs write it: TOML (`"auto"`, `[0]`, `2e10`), else a bare string
/// (`tcp://127.0.0.1:5555`).
toml::table doc_value(const std::string& text) {
  try {
    return toml::parse("v = " + text);
  } catch (const toml::parse_error&) {
    toml::table t;
    t.insert("v", text);
    return t;
  }
}

std::vector<std::string> code_spans(const std::string& text) {
  std::vector<std::string> spans;
  static const std::regex span("`([^`]*)`");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), span); it != std::sregex_iterator(); ++it)
    spans.push_back((*it)[1].str());
  return spans;
}

/// The cells of a Markdown table row ("| a | b |"), `\|` kept inside a cell.
std::vector<std::string> cells(const std::string& row) {
  std::vector<std::string> out;
  std::string cell;
  for (size_t i = 1; i < row.size(); ++i) {
    if (row[i] == '|' && row[i - 1] != '\\') {
      out.push_back(cell);
      cell.clear();
    } else {
      cell += row[i];
    }
  }
  return out;
}

/// Calls f(dotted key, node) for every value of `table` that is not a table.
template <class F>
void for_each_value(const toml::table& table, const std::string& prefix, F&& f) {
  for (const auto& [k, v] : table) {
    const std::string key = prefix + std::string(k.str());
    if (const toml::table* sub = v.as_table())
      for_each_value(*sub, key + ".", f);
    else
      f(key, v);
  }
}

TEST(ConfigDefaults, ExampleConfigShowsTheBuiltInDefaults) {
  const std::string text = source_file("configs/fqd.toml");
  const std::vector<std::string> lines = lines_of(text);
  int checked = 0;
  for_each_value(toml::parse(text), "", [&](const std::string& key, const toml::node& value) {
    if (key.starts_with("streams.")) return;  // per-stream overrides, not defaults
    const std::string& line = lines.at(value.source().begin.line - 1);
    if (line.find("not the default") != std::string::npos) return;
    EXPECT_TRUE(
        is_builtin_default(key, value, "configs/fqd.toml:" + std::to_string(value.source().begin.line)));
    ++checked;
  });
  EXPECT_GT(checked, 50);  // the file's keys were walked
}

// docs/DAEMON.md, "Configuration keys": `key` | `default` | meaning. A row may name two keys
// (`threads.decode` / `threads.encode` | `0` / `0`); `defaults.filter.*` lists `name=value`.
TEST(ConfigDefaults, DaemonDocShowsTheBuiltInDefaults) {
  const std::vector<std::string> lines = lines_of(source_file("docs/DAEMON.md"));
  auto row = std::find(lines.begin(), lines.end(), "| key | default | meaning |");
  ASSERT_NE(row, lines.end());
  int checked = 0;
  for (row += 2; row != lines.end() && row->starts_with("| `"); ++row) {
    const std::vector<std::string> c = cells(*row);
    ASSERT_GE(c.size(), 3u) << *row;
    const std::vector<std::string> keys = code_spans(c[0]);
    const std::string where = "docs/DAEMON.md: " + keys.at(0);
    if (keys[0].ends_with(".*")) {  // a table's keys as name=value
      const std::string table = keys[0].substr(0, keys[0].size() - 1);
      for (const std::string& span : code_spans(c[1])) {
        const size_t eq = span.find('=');
        if (eq == std::string::npos) continue;  // a value named in passing ("qf": the paper)
        const std::string key = table + span.substr(0, eq);
        EXPECT_TRUE(is_builtin_default(key, *doc_value(span.substr(eq + 1)).get("v"), where)) << *row;
        ++checked;
      }
      continue;
    }
    // The default: one value per key before any note in brackets; a row whose default is
    // told in words (http.web_root) shows no value to check.
    std::string shown = c[1].substr(0, c[1].find(" ("));
    const std::vector<std::string> values = code_spans(shown);
    if (std::regex_replace(shown, std::regex("`[^`]*`|/|\\s"), "").size() > 0) continue;
    ASSERT_EQ(values.size(), keys.size()) << *row;
    const std::string table = keys[0].substr(0, keys[0].rfind('.') + 1);
    for (size_t i = 0; i < keys.size(); ++i) {
      const std::string key = keys[i].find('.') == std::string::npos ? table + keys[i] : keys[i];
      EXPECT_TRUE(is_builtin_default(key, *doc_value(values[i]).get("v"), where)) << *row;
      ++checked;
    }
  }
  EXPECT_GT(checked, 50);  // the table was found and read
}

// docs/FQFILTER.md's options: every fqfilter row of the parameter table shows its default
// (fq::Params; --temporal the one --sequence takes, kDefaultTemporal).
TEST(ConfigDefaults, FqfilterDocShowsTheParameterTableDefaults) {
  const std::vector<std::string> lines = lines_of(source_file("docs/FQFILTER.md"));
  const Params defaults;
  for (const ParamRow& row : param_table()) {
    if (!row.on(kFqfilter)) continue;
    const std::string flag = row.flag();
    auto doc = std::find_if(lines.begin(), lines.end(), [&](const std::string& l) {
      return l.starts_with("| `" + flag + " ") || l.starts_with("| `" + flag + "`");
    });
    ASSERT_NE(doc, lines.end()) << flag << " is not in docs/FQFILTER.md's options";
    const std::string shown = cells(*doc).at(1);
    double value = 0;
    if (row.kind == ParamKind::kBool && shown.find("off") != std::string::npos) {
      value = 0;
    } else {
      const std::vector<std::string> spans = code_spans(shown);
      ASSERT_EQ(spans.size(), 1u) << *doc;
      ASSERT_TRUE(parse_param(row, spans[0], value).ok()) << *doc;
    }
    const double expected = std::string_view(row.name) == "temporal" ? kDefaultTemporal : row.get(defaults);
    EXPECT_EQ(format_param(row, value), format_param(row, expected))
        << "docs/FQFILTER.md shows " << shown << " for " << flag;
  }
}

}  // namespace
}  // namespace fq::daemon
