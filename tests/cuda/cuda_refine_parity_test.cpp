// The "qf+" refinement on the CUDA engine against the CPU engine: noisy synthetic shapes
// and the shared real meshes (FQ_MESH_DIR), under every kernel path of the quadric passes
// (the refinement reads base_quadrics' vertex -> triangle table). Skips without a device.
#include <gtest/gtest.h>

#include "eval/noise.h"
#include "io/mesh_io.h"
#include "tests/cuda/parity.h"
#include "tests/support/mesh_dir.h"
#include "tests/support/test_meshes.h"

namespace fq::test {
namespace {

class CudaRefineParity : public CudaTest {};

Params refined() {
  Params p;
  p.filtering.method = FilterMethod::kQuadricRefined;
  return p;
}

TEST_F(CudaRefineParity, NoisyCubeAndSphere) {
  Mesh shapes[] = {make_cube(16), make_icosphere(5)};
  for (Mesh& m : shapes) {
    add_gaussian_noise(m, 0.3, 7);
    expect_parity_for_each(*cpu_, m.view(), refined(), kKernelPaths);
  }
}

// The clean-input guard at a partial strength (the mean normal change over 3 rad: about
// 0.1-0.2 of the result kept) and at its defaults on clean shapes (the input kept).
TEST_F(CudaRefineParity, CleanInputGuard) {
  Params partial = refined();
  partial.filtering.refine.clean_below = 0.f;
  partial.filtering.refine.full_above = 3.f;
  partial.filtering.refine.rough_full = 0.f;  // rough_from must not lie below full_above
  Mesh noisy = make_icosphere(5);
  add_gaussian_noise(noisy, 0.3, 7);
  expect_parity_for_each(*cpu_, noisy.view(), partial, kKernelPaths);
  Mesh shapes[] = {make_cube(16), make_icosphere(5)};
  for (Mesh& m : shapes) expect_parity_for_each(*cpu_, m.view(), refined(), kKernelPaths);
}

// The rough-input run (step 5): taken in full (over rough_full) and blended with the fine
// run (r between rough_from and rough_full).
TEST_F(CudaRefineParity, RoughInputRun) {
  Params full = refined();
  full.filtering.refine.rough_from = 0.2f;
  full.filtering.refine.rough_full = 0.21f;
  Params blended = refined();
  blended.filtering.refine.rough_from = 0.2f;
  blended.filtering.refine.rough_full = 3.f;
  Mesh shapes[] = {make_cube(16), make_icosphere(5)};
  for (Mesh& m : shapes) {
    add_gaussian_noise(m, 0.3, 7);
    expect_parity_for_each(*cpu_, m.view(), full, kKernelPaths);
    expect_parity_for_each(*cpu_, m.view(), blended, kKernelPaths);
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
    expect_parity_for_each(*cpu_, mesh.view(), refined(), {{CudaTuning::kTeamBySize, false}, {0, false}});
  }
}

}  // namespace
}  // namespace fq::test
