// The shared real meshes the "qf+" parity suites run on (FQ_MESH_DIR, tests/support/mesh_dir.h).
#pragma once

#include "tests/support/shared_meshes.h"

namespace fq::test {

inline constexpr const char* kRealMeshes[] = {"fandisk.ply", "bunny.ply", "igea.ply", "crane/crane_0060.drc"};

}  // namespace fq::test
