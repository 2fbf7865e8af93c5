// The "qf+" refinement on the CUDA engine against the CPU engine: noisy synthetic shapes
// and the shared real meshes (FQ_MESH_DIR), under every kernel path of the quadric passes
// and both base-quadric variants (the refinement needs the gather's vertex -> triangle
// table and builds it even when the atomic variant is selected). Skips without a device.
#include <gtest/gtest.h>

#include "eval/noise.h"
#include "proto/mesh_io.h"
#include "tests/cuda/parity.h"
#include "tests/support/mesh_dir.h"
#include "tests/support/test_meshes.h"

namespace fq::test {
namespace {

class CudaRefineParity : public CudaTest {};

Params refined() {
  Params p;
  p.f.method = FilterMethod::kQuadricRefined;
  return p;
}

TEST_F(CudaRefineParity, NoisyCubeAndSphere) {
  Mesh shapes[] = {make_cube(16), make_icosphere(5)};
  for (Mesh& m : shapes) {
    add_gaussian_noise(m, 0.3, 7);
    expect_parity_for_each(*cpu_, *gpu_, m.view(), refined(), "FQ_CUDA_TEAM", kKernelPaths);
    expect_parity_for_each(*cpu_, *gpu_, m.view(), refined(), "FQ_CUDA_BASE", {"gather", "atomic"});
  }
}

TEST_F(CudaRefineParity, RealMeshesWithNoise) {
  for (const char* file : {"fandisk.ply", "bunny.ply", "igea.ply"}) {
    const auto path = find_mesh(file);
    if (!path) GTEST_SKIP() << file << " not found in " << mesh_dir();
    Mesh mesh;
    const Status rs = io::read_mesh(*path, mesh);
    ASSERT_TRUE(rs.ok()) << rs.message();
    add_gaussian_noise(mesh, 0.2, 7);
    std::printf("  %s (%u vertices):\n", file, mesh.num_vertices());
    expect_parity_for_each(*cpu_, *gpu_, mesh.view(), refined(), "FQ_CUDA_TEAM", {"auto", "0"});
  }
}

}  // namespace
}  // namespace fq::test
