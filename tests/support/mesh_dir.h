// Where the shared real meshes are: tests that need one skip cleanly when it is missing.
#pragma once

#include <optional>
#include <string>

namespace fq::test {

/// The folder named by the environment variable FQ_MESH_DIR, or else the folder
/// configured at build time (CMake cache variable FQ_MESH_DIR).
std::string mesh_dir();

/// Full path of `file_name` in mesh_dir(), or nothing when that file does not exist.
std::optional<std::string> find_mesh(const std::string& file_name);

}  // namespace fq::test
