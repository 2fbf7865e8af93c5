#include "tests/cuda/parity.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <utility>

#include "kernels/cpu_engine.h"
#include "kernels/cuda_engine.h"

namespace fq::test {

PositionError position_error(const std::vector<float>& reference, const std::vector<float>& candidate) {
  const size_t n = reference.size() / 3;
  double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
  for (size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], double(reference[3 * i + k]));
      hi[k] = std::max(hi[k], double(reference[3 * i + k]));
    }
  }
  const double diag = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                                (hi[2] - lo[2]) * (hi[2] - lo[2]));
  std::vector<double> d(n);
  for (size_t i = 0; i < n; ++i) {
    double s = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double e = double(reference[3 * i + k]) - double(candidate[3 * i + k]);
      s += e * e;
    }
    d[i] = std::isfinite(s) ? std::sqrt(s) / diag : 1e300;  // NaN never passes
  }
  PositionError out;
  if (n == 0) return out;
  std::sort(d.begin(), d.end());
  out.p99 = d[std::min(n - 1, size_t(std::ceil(0.99 * double(n))) - 1)];
  out.max = d.back();
  return out;
}

namespace {

// Vertices covered by mapping each label of `from` to its most overlapping label of `to`.
double majority_fraction(const std::vector<uint32_t>& from, const std::vector<uint32_t>& to) {
  std::map<std::pair<uint32_t, uint32_t>, uint32_t> overlap;
  for (size_t i = 0; i < from.size(); ++i) ++overlap[{from[i], to[i]}];
  std::map<uint32_t, uint32_t> best;
  for (const auto& [key, count] : overlap) best[key.first] = std::max(best[key.first], count);
  uint64_t agree = 0;
  for (const auto& [label, count] : best) agree += count;
  return from.empty() ? 1.0 : double(agree) / double(from.size());
}

}  // namespace

double label_agreement(const std::vector<uint32_t>& reference, const std::vector<uint32_t>& candidate) {
  if (reference.size() != candidate.size()) return 0.0;
  return std::min(majority_fraction(reference, candidate), majority_fraction(candidate, reference));
}

std::string Parity::summary() const {
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "positions p99 %.3g max %.3g (of bbox diagonal); labels agree %.5f; clusters cpu %u gpu %u",
                pos.p99, pos.max, labels, cpu.num_clusters, gpu.num_clusters);
  return buf;
}

void run_both(Engine& cpu, Engine& gpu, const MeshView& mesh, const Params& params, Parity& out) {
  const Status sc = cpu.process(mesh, params, out.cpu);
  ASSERT_TRUE(sc.ok()) << sc.message();
  rerun_gpu(gpu, mesh, params, out);
}

std::string describe(const CudaTuning& tuning) {
  std::string team = tuning.team == CudaTuning::kTeamBySize ? "by size" : std::to_string(tuning.team);
  return "team " + team + (tuning.fast_exp ? ", fast exp" : "");
}

std::unique_ptr<Engine> cuda_engine_with(const CudaTuning& tuning) {
  Status why;
  std::unique_ptr<Engine> e = make_cuda_engine(0, &why, tuning);
  EXPECT_TRUE(e) << describe(tuning) << ": " << why.message();
  return e;
}

void expect_parity_for_each(Engine& cpu, const MeshView& mesh, const Params& params,
                            std::initializer_list<CudaTuning> tunings,
                            const std::function<void(const Parity&)>& extra) {
  Parity p;
  const Status sc = cpu.process(mesh, params, p.cpu);
  ASSERT_TRUE(sc.ok()) << sc.message();
  for (const CudaTuning& tuning : tunings) {
    SCOPED_TRACE(describe(tuning));
    const std::unique_ptr<Engine> gpu = cuda_engine_with(tuning);
    ASSERT_TRUE(gpu);
    rerun_gpu(*gpu, mesh, params, p);
    expect_parity(p, params);
    if (extra) extra(p);
  }
}

void rerun_gpu(Engine& gpu, const MeshView& mesh, const Params& params, Parity& out) {
  const Status sg = gpu.process(mesh, params, out.gpu);
  ASSERT_TRUE(sg.ok()) << sg.message();
  ASSERT_EQ(out.cpu.positions.size(), out.gpu.positions.size());
  out.pos = position_error(out.cpu.positions, out.gpu.positions);
  if (params.cluster) out.labels = label_agreement(out.cpu.labels, out.gpu.labels);
}

void expect_parity(const Parity& p, const Params& params) {
  SCOPED_TRACE(p.summary());
  std::printf("  parity: %s\n", p.summary().c_str());
  // The device reduces the mean edge in another order: equal up to rounding.
  EXPECT_NEAR(p.gpu.mean_edge, p.cpu.mean_edge, 1e-12 * p.cpu.mean_edge);
  if (params.filter) {
    EXPECT_LE(p.pos.p99, 1e-4);
    EXPECT_LE(p.pos.max, 1e-2);
  } else {
    EXPECT_EQ(p.cpu.positions, p.gpu.positions);  // the input, untouched
  }
  if (params.cluster) {
    ASSERT_EQ(p.gpu.labels.size(), p.cpu.labels.size());
    for (uint32_t l : p.gpu.labels) ASSERT_LT(l, p.gpu.num_clusters);
    EXPECT_GE(p.labels, 0.99);
    const double slack = std::max(1.0, 0.02 * p.cpu.num_clusters);
    EXPECT_LE(std::abs(double(p.gpu.num_clusters) - double(p.cpu.num_clusters)), slack);
  }
}

void CudaTest::SetUp() {
  Status why;
  gpu_ = make_cuda_engine(0, &why);
  if (!gpu_) {
    ASSERT_EQ(why.code(), StatusCode::kUnavailable) << why.message();
    GTEST_SKIP() << "no CUDA device: " << why.message();
  }
  cpu_ = std::make_unique<CpuEngine>();
}

}  // namespace fq::test
