// Comparison of two engines' results on one frame, and a fixture that holds a CUDA engine
// (or skips the test when there is no device).
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <initializer_list>
#include <memory>
#include <string>
#include <vector>

#include "core/mesh_view.h"
#include "kernels/engine.h"

namespace fq::test {

/// Per-vertex distance between two position arrays, relative to the diagonal of the
/// bounding box of `reference`.
struct PositionError {
  double p99 = 0.0;  ///< 99th percentile
  double max = 0.0;
};
PositionError position_error(const std::vector<float>& reference, const std::vector<float>& candidate);

/// Fraction of vertices whose label agrees after mapping each cluster of one labelling to
/// the cluster of the other it overlaps most (majority mapping), taken both ways; the
/// smaller of the two fractions.
double label_agreement(const std::vector<uint32_t>& reference, const std::vector<uint32_t>& candidate);

/// Both engines' results of one frame, and a summary line for test logs.
struct Parity {
  FrameResult cpu, gpu;
  PositionError pos;
  double labels = 1.0;
  std::string summary() const;
};

/// Runs `mesh` through both engines with `params` (ASSERTs both succeed).
void run_both(Engine& cpu, Engine& gpu, const MeshView& mesh, const Params& params, Parity& out);
/// Runs only the GPU engine and compares with the CPU result already in `out.cpu`.
void rerun_gpu(Engine& gpu, const MeshView& mesh, const Params& params, Parity& out);

/// The CUDA engine's kernel paths: the default team per vertex, one thread per vertex
/// calling the math headers directly (team 0), and fixed teams of 1 and 32 lanes.
inline constexpr std::initializer_list<CudaTuning> kKernelPaths = {
    {CudaTuning::kTeamBySize, false}, {0, false}, {1, false}, {32, false}};

/// "team 4, fast exp" and the like, for traces.
std::string describe(const CudaTuning& tuning);

/// A CUDA engine on device 0 with `tuning` (fails the test when none can be made).
std::unique_ptr<Engine> cuda_engine_with(const CudaTuning& tuning);

/// The stated tolerances: mean edge equal up to 1e-12 (relative); positions within 1e-4
/// of the bbox diagonal at the 99th percentile and 1e-2 at most; labels agreeing on >= 99%
/// of vertices; cluster counts within 2% (at least 1).
void expect_parity(const Parity& p, const Params& params);

/// Runs the CPU engine once and a CUDA engine of each tuning once, expecting parity each
/// time; `extra` (optional) adds checks of its own on each GPU result.
void expect_parity_for_each(Engine& cpu, const MeshView& mesh, const Params& params,
                            std::initializer_list<CudaTuning> tunings,
                            const std::function<void(const Parity&)>& extra = {});

/// Holds a CUDA engine on device 0; skips the test when none can be made.
class CudaTest : public ::testing::Test {
 protected:
  void SetUp() override;
  std::unique_ptr<Engine> gpu_;
  std::unique_ptr<Engine> cpu_;
};

}  // namespace fq::test
