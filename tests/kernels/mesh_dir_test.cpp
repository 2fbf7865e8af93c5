// Location of the shared meshes (tests/support/mesh_dir.h): the environment variable
// FQ_MESH_DIR wins over the folder configured at build time.
#include "tests/support/mesh_dir.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

namespace fq::test {
namespace {

// Sets FQ_MESH_DIR for one test and restores the previous value.
class ScopedMeshDir {
 public:
  explicit ScopedMeshDir(const char* value) {
    if (const char* old = std::getenv("FQ_MESH_DIR")) old_ = old;
    if (value) {
      setenv("FQ_MESH_DIR", value, 1);
    } else {
      unsetenv("FQ_MESH_DIR");
    }
  }
  ~ScopedMeshDir() {
    if (old_) {
      setenv("FQ_MESH_DIR", old_->c_str(), 1);
    } else {
      unsetenv("FQ_MESH_DIR");
    }
  }

 private:
  std::optional<std::string> old_;
};

TEST(KernelMeshDir, EnvironmentOverridesTheBuildDefault) {
  const std::filesystem::path dir = std::filesystem::path(testing::TempDir()) / "fq_mesh_dir_test";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "tiny.ply") << "ply\n";
  ScopedMeshDir env(dir.c_str());
  EXPECT_EQ(mesh_dir(), dir.string());
  ASSERT_TRUE(find_mesh("tiny.ply").has_value());
  EXPECT_EQ(*find_mesh("tiny.ply"), (dir / "tiny.ply").string());
  EXPECT_FALSE(find_mesh("missing.ply").has_value());
  EXPECT_FALSE(find_mesh("").has_value());  // the folder itself is not a mesh
  std::filesystem::remove_all(dir);
}

TEST(KernelMeshDir, EmptyOrUnsetUsesTheConfiguredFolder) {
  std::string configured;
  {
    ScopedMeshDir env(nullptr);
    configured = mesh_dir();
  }
  EXPECT_FALSE(configured.empty());  // FQ_DEFAULT_MESH_DIR reached the support library
  ScopedMeshDir env("");
  EXPECT_EQ(mesh_dir(), configured);
}

}  // namespace
}  // namespace fq::test
