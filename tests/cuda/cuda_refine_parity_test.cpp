// "qf+" on the CUDA engine against the CPU engine: the noise estimate (the same samples, the
// same host reduction) and the filtered positions, on noisy and clean synthetic shapes, with a
// given noise and strength, with fractional rounds, with clustering beside it (every kernel
// path of the quadric passes), and on the shared real meshes (FQ_MESH_DIR). Skips without a
// device.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "eval/capture_sequence.h"
#include "eval/noise.h"
#include "kernels/cpu_engine.h"
#include "tests/cuda/parity.h"
#include "tests/cuda/real_meshes.h"
#include "tests/support/mesh_dir.h"
#include "tests/support/test_meshes.h"

namespace fq::test {
namespace {

class CudaRefineParity : public CudaTest {};

// Both engines' estimates: the samples are the same math in double precision on both sides,
// reduced on the host by the same code; contraction into fused multiply-adds on the device
// leaves them within 1e-4 of each other (relative).
void expect_same_noise(const Parity& p) {
  EXPECT_NEAR(p.gpu.noise_estimate, p.cpu.noise_estimate, 1e-4f * std::fmax(p.cpu.noise_estimate, 1e-3f));
  EXPECT_NEAR(p.gpu.filter_noise, p.cpu.filter_noise, 1e-4f * std::fmax(p.cpu.filter_noise, 1e-3f));
  EXPECT_NEAR(p.gpu.noise_directional, p.cpu.noise_directional,
              1e-4f * std::fmax(p.cpu.noise_directional, 1e-3f));
  EXPECT_NEAR(p.gpu.noise_alignment, p.cpu.noise_alignment, 1e-4f);
}

const std::initializer_list<CudaTuning> kDefault = {{CudaTuning::kTeamBySize, false}};

TEST_F(CudaRefineParity, NoisyCubeAndSphere) {
  Mesh shapes[] = {make_cube(16), make_icosphere(5)};
  for (Mesh& m : shapes) {
    for (double s : {0.05, 0.3}) {
      Mesh noisy = m;
      add_gaussian_noise(noisy, s, 7);
      expect_parity_for_each(*cpu_, noisy.view(), Params{}, kDefault, expect_same_noise);
    }
  }
}

// Noise along one direction (eval/noise.h, depth): the directional estimate, its plan (a larger
// tangential share, the slide allowance along the direction) and the result agree. The sphere
// reads it; the cube does not (its faces see z head-on or edge-on: no vertex away from a crease
// shows the noise both along its normal and within its plane), and both engines agree on that.
TEST_F(CudaRefineParity, DepthNoiseAlongOneDirection) {
  Mesh shapes[] = {make_icosphere(5), make_cube(16)};
  for (int k = 0; k < 2; ++k) {
    for (double s : {0.1, 0.2}) {
      Mesh noisy = shapes[k];
      add_depth_noise(noisy, s, 11);
      expect_parity_for_each(*cpu_, noisy.view(), Params{}, kDefault, [k](const Parity& p) {
        expect_same_noise(p);
        if (k == 0) EXPECT_GT(p.cpu.noise_directional, 0.f);
      });
    }
  }
}

TEST_F(CudaRefineParity, CleanShapes) {
  Mesh shapes[] = {make_cube(16), make_icosphere(5)};
  for (Mesh& m : shapes) expect_parity_for_each(*cpu_, m.view(), Params{}, kDefault, expect_same_noise);
}

// A given noise, a strength, and a noise whose plan has a fractional last round (1 + 16σ²
// rounds: 3.56 at σ = 0.4).
TEST_F(CudaRefineParity, GivenNoiseStrengthAndFractionalRounds) {
  Mesh m = make_icosphere(5);
  add_gaussian_noise(m, 0.3, 9);
  Params given;
  given.filtering.refine.known_noise = 0.4f;
  expect_parity_for_each(*cpu_, m.view(), given, kDefault, expect_same_noise);
  Params strong;
  strong.filtering.refine.strength = 1.7f;
  expect_parity_for_each(*cpu_, m.view(), strong, kDefault, expect_same_noise);
}

// Clustering beside "qf+": the quadric passes run for the labels, under every kernel path.
TEST_F(CudaRefineParity, WithClustering) {
  Mesh m = make_cube(16);
  add_gaussian_noise(m, 0.2, 7);
  Params p;
  p.cluster = true;
  expect_parity_for_each(*cpu_, m.view(), p, kKernelPaths, expect_same_noise);
}

TEST_F(CudaRefineParity, RealMeshesWithNoise) {
  for (const char* file : kRealMeshes) {
    const std::optional<Mesh> mesh = read_real_mesh(file);
    if (!mesh) GTEST_SKIP() << file << " not found in " << mesh_dir();
    for (double s : {0.05, 0.2}) {
      Mesh noisy = *mesh;
      add_gaussian_noise(noisy, s, 7);
      std::printf("  %s (%u vertices), noise %.2f:\n", file, mesh->num_vertices(), s);
      expect_parity_for_each(*cpu_, noisy.view(), Params{}, kDefault, expect_same_noise);
    }
    Mesh depth = *mesh;
    add_depth_noise(depth, 0.2, 7);
    std::printf("  %s, depth noise 0.20:\n", file);
    expect_parity_for_each(*cpu_, depth.view(), Params{}, kDefault, expect_same_noise);
  }
}

// Temporal filtering with the connectivity kept (track A, kernels/temporal_ids.h: the same host
// step in front of both engines' runs) gives the same results within the stated tolerances,
// frame after frame, with the same weight of the history.
TEST_F(CudaRefineParity, TemporalSequence) {
  const Mesh sphere = make_icosphere(5);
  // Alone, and with clustering on the filtered mesh, which reads the frame's positions after
  // the temporal step on both engines (kernels/engine_process.cpp).
  for (const bool cluster : {false, true}) {
    Params p;
    p.filtering.temporal = 0.75f;
    p.cluster = cluster;
    p.clustering.target_clusters = cluster ? 12 : 0;
    TemporalHistory cpu_history, gpu_history;
    cpu_->set_history(&cpu_history);
    gpu_->set_history(&gpu_history);
    for (uint64_t seed = 1; seed <= 4; ++seed) {
      Mesh frame = sphere;
      add_gaussian_noise(frame, 0.2, seed);
      Parity r;
      run_both(*cpu_, *gpu_, frame.view(), p, r);
      expect_parity(r, p);
      EXPECT_NEAR(r.gpu.prior_share, r.cpu.prior_share, 0.01f) << "frame " << seed;
      EXPECT_NEAR(r.gpu.prior_coverage, r.cpu.prior_coverage, 0.001f) << "frame " << seed;
      EXPECT_EQ(r.gpu.prior_coverage > 0.f, seed > 1);
      EXPECT_EQ(r.gpu.temporal_track, r.cpu.temporal_track);
      EXPECT_EQ(r.gpu.temporal_track, seed > 1 ? TemporalTrack::kIds : TemporalTrack::kSpace);
    }
    cpu_->set_history(nullptr);
    gpu_->set_history(nullptr);
    EXPECT_EQ(gpu_history.frames, 4u);
    TemporalScratch scratch;
    settle_history_normals(gpu_history, scratch, 2);  // track A leaves them until they are read
    EXPECT_EQ(gpu_history.normals.size(), gpu_history.positions.size()) << "the host history is whole";
  }
}

// A frame far from the last (a scene cut) restarts the history on the device too, and is left
// exactly as the CUDA engine filters it alone. Its first triangle's corners are turned (the
// same surface, another triangle array): with the connectivity kept, track A would read the
// jump as a motion its ids follow.
TEST_F(CudaRefineParity, TemporalSceneCutLeavesTheFrameAlone) {
  const Mesh sphere = make_icosphere(4);
  Params p;
  p.filtering.temporal = 0.75f;
  Mesh first = sphere, elsewhere = sphere;
  add_gaussian_noise(first, 0.2, 1);
  for (uint32_t v = 0; v < elsewhere.num_vertices(); ++v) elsewhere.positions[3 * size_t(v)] += 10.f;
  add_gaussian_noise(elsewhere, 0.2, 2);
  std::rotate(elsewhere.triangles.begin(), elsewhere.triangles.begin() + 1, elsewhere.triangles.begin() + 3);
  TemporalHistory history;
  FrameResult r, cut, single;
  gpu_->set_history(&history);
  ASSERT_TRUE(gpu_->process(first.view(), p, r).ok());
  ASSERT_TRUE(gpu_->process(elsewhere.view(), p, cut).ok());
  gpu_->set_history(nullptr);
  const std::unique_ptr<Engine> alone = cuda_engine_with({});
  ASSERT_TRUE(alone);
  ASSERT_TRUE(alone->process(elsewhere.view(), p, single).ok());
  EXPECT_TRUE(cut.history_reset);
  EXPECT_EQ(cut.prior_coverage, 0.f);
  EXPECT_EQ(history.resets, 1u);
  EXPECT_EQ(history.frames, 1u) << "the cut frame starts the history again";
  EXPECT_EQ(cut.positions, single.positions);
}

// Frame t of a stream: `sphere` shifted by `offset` and moved by 0.007 a frame (a third of its
// mean edge), turned by a degree a frame, with fresh noise and its vertices renumbered, as a
// capture system re-meshes (eval/capture_sequence.h).
Mesh stream_frame(const Mesh& sphere, int t, float offset, uint64_t seed) {
  Mesh m = sphere;
  for (uint32_t v = 0; v < m.num_vertices(); ++v) m.positions[3 * size_t(v)] += offset + 0.007f * float(t);
  return capture_frame(m, double(t), 0.2, seed);
}

// One frame through `engine` with `history`, beside the CPU engine with `reference`.
void expect_temporal_parity(Engine& cpu, TemporalHistory& reference, Engine& engine, TemporalHistory& history,
                            const Mesh& frame, const Params& p) {
  Parity r;
  cpu.set_history(&reference);
  const Status sc = cpu.process(frame.view(), p, r.cpu);
  cpu.set_history(nullptr);
  ASSERT_TRUE(sc.ok()) << sc.message();
  engine.set_history(&history);
  const Status se = engine.process(frame.view(), p, r.gpu);
  engine.set_history(nullptr);
  ASSERT_TRUE(se.ok()) << se.message();
  r.pos = position_error(r.cpu.positions, r.gpu.positions);
  expect_parity(r, p);
  EXPECT_NEAR(r.gpu.prior_share, r.cpu.prior_share, 0.01f);
  EXPECT_FALSE(r.gpu.history_reset);
  // The motion the next frame's estimate starts from (input units), as the CPU engine found it.
  // A near tie between two prior vertices may go either way on the two engines (the host's
  // index, the device's grid), and such a match moves its neighbours' motion by up to a fifth
  // of a mean edge (measured on an H200 host: 0.06-0.22 at the worst vertex, frames 3-6):
  // the mean difference and the share of values apart by more than 0.05 mean edges are held.
  ASSERT_EQ(history.motion.size(), reference.motion.size());
  ASSERT_EQ(history.motion.empty(), history.frames <= 1);
  double sum = 0.0;
  size_t apart = 0;
  for (size_t i = 0; i < history.motion.size(); ++i) {
    const double d = std::abs(double(history.motion[i]) - double(reference.motion[i])) / r.cpu.mean_edge;
    sum += d;
    apart += d > 0.05 ? 1 : 0;
  }
  if (!history.motion.empty()) {
    EXPECT_LT(sum / double(history.motion.size()), 0.002) << "mean edges";
    EXPECT_LT(double(apart), 0.01 * double(history.motion.size()))
        << "values more than 0.05 mean edges apart";
    std::printf("  motion: mean difference %.2e mean edges, %zu of %zu values apart\n",
                sum / double(history.motion.size()), apart, history.motion.size());
  }
}

// A stream may move between engines (fqd hands its history to whichever runs the frame): the
// history the CUDA engine leaves on the host is the CPU engine's to follow and the other way
// round, as if one engine ran every frame; runs of the CUDA engine read its device copy.
TEST_F(CudaRefineParity, TemporalHistoryMovesBetweenEngines) {
  const Mesh sphere = make_icosphere(5);
  Params p;
  p.filtering.temporal = 0.75f;
  CpuEngine other;
  TemporalHistory reference, moving;
  const char* engines = "GCGGCCG";  // every hand-over: to and from the device, and staying
  for (int t = 0; engines[t] != 0; ++t) {
    SCOPED_TRACE("frame " + std::to_string(t) + " on " + engines[t]);
    Engine& engine = engines[t] == 'G' ? *gpu_ : static_cast<Engine&>(other);
    expect_temporal_parity(*cpu_, reference, engine, moving, stream_frame(sphere, t, 0.f, 10 + t), p);
  }
  EXPECT_EQ(moving.frames, 7u);
  EXPECT_EQ(moving.resets, 0u);
}

// Streams whose frames take turns on one CUDA engine each follow their own history: from the
// engine's device copies while they are as few as its copies, uploaded from the host when more
// streams push each other's copies out.
TEST_F(CudaRefineParity, TemporalStreamsTakeTurnsOnOneEngine) {
  const Mesh sphere = make_icosphere(4);
  Params p;
  p.filtering.temporal = 0.75f;
  for (int streams : {2, 6}) {
    SCOPED_TRACE(std::to_string(streams) + " streams");
    std::vector<TemporalHistory> reference(streams), history(streams);
    for (int t = 0; t < 4; ++t) {
      for (int k = 0; k < streams; ++k) {
        SCOPED_TRACE("stream " + std::to_string(k) + " frame " + std::to_string(t));
        const Mesh frame = stream_frame(sphere, t, 0.5f * float(k), 100 * k + t);
        expect_temporal_parity(*cpu_, reference[k], *gpu_, history[k], frame, p);
      }
    }
    for (const TemporalHistory& h : history) EXPECT_EQ(h.frames, 4u);
  }
}

}  // namespace
}  // namespace fq::test
