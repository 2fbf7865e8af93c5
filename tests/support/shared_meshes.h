// The shared real meshes (FQ_MESH_DIR, tests/support/mesh_dir.h): every one of them, and
// how a test reads one (through fq_io, so the Draco files too).
#pragma once

#include <gtest/gtest.h>

#include <optional>

#include "core/mesh_view.h"
#include "io/mesh_io.h"
#include "tests/support/mesh_dir.h"

namespace fq::test {

/// Every shared mesh, smallest first (the crane sequence by its first frame).
inline constexpr const char* kSharedMeshes[] = {
    "fandisk.ply", "max_planck.ply",       "gargoyle.ply", "bunny.ply",         "armadillo.ply",
    "igea.ply",    "crane/crane_0000.drc", "dragon.ply",   "armadillo_x16.drc", "igea_x16.drc"};

/// `file` read from mesh_dir(): nothing where the file is not there (the test skips), and a
/// failure of the test where it is there but does not read.
inline std::optional<Mesh> read_real_mesh(const char* file) {
  const auto path = find_mesh(file);
  if (!path) return std::nullopt;
  Mesh mesh;
  if (const Status rs = io::read_mesh(*path, mesh); !rs.ok()) {
    ADD_FAILURE() << file << ": " << rs.message();
    return std::nullopt;
  }
  return mesh;
}

}  // namespace fq::test
