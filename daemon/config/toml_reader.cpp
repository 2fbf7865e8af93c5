#include "daemon/config/toml_reader.h"

#include <cmath>

#include "daemon/config/echo_value.h"

namespace fq::daemon {

TomlReader::TomlReader(const toml::table& table, std::string source, std::string path)
    : table_(table), source_(std::move(source)), path_(std::move(path)) {}

std::string TomlReader::name(const char* key) const { return path_.empty() ? key : path_ + "." + key; }

void TomlReader::fail(const char* key, const std::string& what) {
  if (!error_.ok()) return;
  std::string where = source_;
  if (const toml::node* n = table_.get(key)) where += ":" + std::to_string(n->source().begin.line);
  error_ = invalid_argument(where + ": " + echo_value(name(key), 4 * kEchoBytes) + " " + what);
}

const toml::node* TomlReader::get(const char* key) {
  known_.insert(key);
  return table_.get(key);
}

void TomlReader::read(const char* key, std::string& out) {
  const toml::node* n = get(key);
  if (!n) return;
  if (auto v = n->value_exact<std::string>())
    out = *v;
  else
    fail(key, "must be a string");
}

void TomlReader::read(const char* key, bool& out) {
  const toml::node* n = get(key);
  if (!n) return;
  if (auto v = n->value_exact<bool>())
    out = *v;
  else
    fail(key, "must be true or false");
}

void TomlReader::read(const char* key, float& out) {
  double d = out;
  read(key, d, -1e30, 1e30);
  out = static_cast<float>(d);
}

void TomlReader::read(const char* key, double& out, double lo, double hi) {
  const toml::node* n = get(key);
  if (!n) return;
  std::optional<double> v;
  if (n->is_floating_point())
    v = n->value_exact<double>();
  else if (n->is_integer())
    v = static_cast<double>(*n->value_exact<int64_t>());
  if (!v) return fail(key, "must be a number");
  if (!std::isfinite(*v) || *v < lo || *v > hi)
    return fail(key, "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "] (got " +
                         std::to_string(*v) + ")");
  out = *v;
}

bool TomlReader::integer(const char* key, int64_t lo, int64_t hi, int64_t& out) {
  const toml::node* n = get(key);
  if (!n) return false;
  auto v = n->value_exact<int64_t>();
  if (!v) return fail(key, "must be an integer"), false;
  if (*v < lo || *v > hi)
    return fail(key, "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "] (got " +
                         std::to_string(*v) + ")"),
           false;
  out = *v;
  return true;
}

void TomlReader::read(const char* key, int& out, int64_t lo, int64_t hi) {
  if (int64_t v; integer(key, lo, hi, v)) out = static_cast<int>(v);
}
void TomlReader::read(const char* key, uint32_t& out, int64_t lo, int64_t hi) {
  if (int64_t v; integer(key, lo, hi, v)) out = static_cast<uint32_t>(v);
}
void TomlReader::read(const char* key, uint64_t& out, int64_t lo, int64_t hi) {
  if (int64_t v; integer(key, lo, hi, v)) out = static_cast<uint64_t>(v);
}

void TomlReader::read(const char* key, std::vector<int>& out, int64_t lo, int64_t hi) {
  const toml::node* n = get(key);
  if (!n) return;
  const toml::array* a = n->as_array();
  if (!a) return fail(key, "must be an array of integers");
  std::vector<int> values;
  for (const toml::node& e : *a) {
    auto v = e.value_exact<int64_t>();
    if (!v || *v < lo || *v > hi)
      return fail(key, "must hold integers in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    values.push_back(static_cast<int>(*v));
  }
  out = std::move(values);
}

void TomlReader::read(const char* key, std::vector<std::string>& out) {
  const toml::node* n = get(key);
  if (!n) return;
  const toml::array* a = n->as_array();
  if (!a) return fail(key, "must be an array of strings");
  std::vector<std::string> values;
  for (const toml::node& e : *a) {
    auto v = e.value_exact<std::string>();
    if (!v) return fail(key, "must hold strings");
    values.push_back(*v);
  }
  out = std::move(values);
}

const toml::table* TomlReader::table(const char* key) {
  const toml::node* n = get(key);
  if (!n) return nullptr;
  if (const toml::table* t = n->as_table()) return t;
  fail(key, "must be a table");
  return nullptr;
}

Status TomlReader::finish() {
  if (!error_.ok()) return error_;
  for (const auto& [k, v] : table_) {
    const std::string key(k.str());
    if (known_.count(key)) continue;
    return invalid_argument(source_ + ":" + std::to_string(v.source().begin.line) + ": unknown key '" +
                            echo_value(name(key.c_str())) + "'");
  }
  return {};
}

}  // namespace fq::daemon
