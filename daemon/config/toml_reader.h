// Typed reads from one TOML table that remember which keys were read, so that a key the
// daemon does not know (a typo) is reported instead of silently ignored.
#pragma once

#include <toml++/toml.h>

#include <cstdint>
#include <set>
#include <string>
#include <vector>

#include "common/status.h"

namespace fq::daemon {

class TomlReader {
 public:
  /// `path` is the dotted name of the table ("" for the root), used in messages.
  TomlReader(const toml::table& table, std::string source, std::string path);

  /// Each read leaves `out` unchanged when the key is absent and records an error when it
  /// has the wrong type or is outside [lo, hi]. The first error is kept.
  void read(const char* key, std::string& out);
  void read(const char* key, bool& out);
  void read(const char* key, float& out);
  void read(const char* key, double& out, double lo, double hi);
  void read(const char* key, int& out, int64_t lo, int64_t hi);
  void read(const char* key, uint32_t& out, int64_t lo, int64_t hi);
  void read(const char* key, uint64_t& out, int64_t lo, int64_t hi);
  void read(const char* key, std::vector<int>& out, int64_t lo, int64_t hi);
  void read(const char* key, std::vector<std::string>& out);

  /// The sub-table `key`, or null when absent (an error when it is not a table).
  const toml::table* table(const char* key);
  /// The raw node of `key` (marked as known), or null when absent: for values of mixed type.
  const toml::node* raw(const char* key) { return get(key); }
  /// Records an error about `key` (with its line) unless one is already recorded.
  void fail(const char* key, const std::string& what);
  /// Dotted name of `key` in this table.
  std::string name(const char* key) const;

  /// The first error, or an "unknown key" error for any key never read or marked.
  Status finish();
  const std::string& source() const { return source_; }

 private:
  const toml::node* get(const char* key);
  bool integer(const char* key, int64_t lo, int64_t hi, int64_t& out);

  const toml::table& table_;
  std::string source_;
  std::string path_;
  std::set<std::string> known_;
  Status error_;
};

}  // namespace fq::daemon
