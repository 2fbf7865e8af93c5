#include "tests/support/mesh_dir.h"

#include <cstdlib>
#include <filesystem>

#ifndef FQ_DEFAULT_MESH_DIR
#define FQ_DEFAULT_MESH_DIR ""
#endif

namespace fq::test {

std::string mesh_dir() {
  // An empty FQ_MESH_DIR counts as unset, so `FQ_MESH_DIR= ctest` keeps the default.
  if (const char* env = std::getenv("FQ_MESH_DIR"); env != nullptr && env[0] != '\0') return env;
  return FQ_DEFAULT_MESH_DIR;
}

std::optional<std::string> find_mesh(const std::string& file_name) {
  const std::string dir = mesh_dir();
  if (dir.empty()) return std::nullopt;
  const std::filesystem::path path = std::filesystem::path(dir) / file_name;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return std::nullopt;
  return path.string();
}

}  // namespace fq::test
