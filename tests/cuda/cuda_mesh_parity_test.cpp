// The CUDA engine against the CPU engine on the shared real meshes (FQ_MESH_DIR), at the
// paper's parameter rows (Tables 2 and 3). Skips without a device or without the mesh.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "io/mesh_io.h"
#include "tests/cuda/parity.h"
#include "tests/support/mesh_dir.h"

namespace fq::test {
namespace {

struct Row {
  const char* file;
  float sigma_s, sigma_r;
  bool cluster;
  float sigma_d, sigma_q, theta;
  FilterMethod method = FilterMethod::kQuadric;
};

void PrintTo(const Row& r, std::ostream* os) { *os << r.file << " sigma_s " << r.sigma_s; }

class CudaMeshParity : public CudaTest, public ::testing::WithParamInterface<Row> {};

TEST_P(CudaMeshParity, MatchesCpuEngine) {
  const Row& row = GetParam();
  const auto path = find_mesh(row.file);
  if (!path) GTEST_SKIP() << row.file << " not found in " << mesh_dir();
  Mesh mesh;
  const Status rs = io::read_mesh(*path, mesh);
  ASSERT_TRUE(rs.ok()) << rs.message();
  Params params;
  params.filtering.method = row.method;
  params.filtering.sigma_s = row.sigma_s;
  params.filtering.sigma_r = row.sigma_r;
  params.cluster = row.cluster;
  params.clustering.sigma_d = row.sigma_d;
  params.clustering.sigma_q = row.sigma_q;
  params.clustering.theta = row.theta;
  Parity p;
  run_both(*cpu_, *gpu_, mesh.view(), params, p);
  std::printf("  %s (%u vertices), default kernels:\n", row.file, mesh.num_vertices());
  expect_parity(p, params);
  const CudaTuning fast_exp{CudaTuning::kTeamBySize, true}, one_thread{0, false};
  for (const CudaTuning& tuning : {fast_exp, one_thread}) {
    const std::unique_ptr<Engine> gpu = cuda_engine_with(tuning);
    ASSERT_TRUE(gpu);
    rerun_gpu(*gpu, mesh.view(), params, p);
    std::printf("  %s:\n", describe(tuning).c_str());
    expect_parity(p, params);
  }
}

// Table 2 (filter) and Table 3 (clustering) rows on the meshes of similar size.
INSTANTIATE_TEST_SUITE_P(PaperRows, CudaMeshParity,
                         ::testing::Values(Row{"fandisk.ply", 3.f, 0.4f, false, 0, 0, 0},
                                           Row{"fandisk.ply", 3.f, 0.4f, false, 0, 0, 0,
                                               FilterMethod::kBilateral},
                                           Row{"bunny.ply", 5.f, 2.f, false, 0, 0, 0},
                                           Row{"bunny.ply", 3.f, 1.f, true, 5.f, 0.8f, 0.9f},
                                           Row{"igea.ply", 3.f, 0.4f, false, 0, 0, 0},
                                           Row{"igea.ply", 2.f, 1.f, true, 6.f, 1.f, 0.87f},
                                           Row{"armadillo.ply", 2.f, 1.f, true, 5.f, 1.f, 0.75f},
                                           Row{"dragon.ply", 5.5f, 1.f, false, 0, 0, 0},
                                           Row{"dragon.ply", 2.f, 1.f, true, 6.f, 1.f, 0.75f}),
                         [](const ::testing::TestParamInfo<Row>& info) {
                           std::string name = info.param.file;
                           name = name.substr(0, name.find('.'));
                           return name + "_" + std::to_string(info.index);
                         });

}  // namespace
}  // namespace fq::test
