// Temporal filtering (kernels/temporal.h) through the CPU engine: a still surface seen again
// with fresh noise gets better than each frame alone; a moving one is not made worse; vertex
// ids play no part; a scene cut restarts the history and leaves that frame as it was alone;
// temporal 0 is the per-frame filter exactly.
#include "kernels/temporal.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numeric>
#include <random>
#include <vector>

#include "core/cancel_token.h"
#include "eval/error_metrics.h"
#include "eval/noise.h"
#include "kernels/cpu_engine.h"
#include "tests/support/test_meshes.h"

namespace fq {
namespace {

Params temporal_params(float temporal) {
  Params p;  // qf+, the default filter
  p.filtering.temporal = temporal;
  return p;
}

Mesh noisy(const Mesh& clean, uint64_t seed) {
  Mesh m = clean;
  add_gaussian_noise(m, 0.2, seed);
  return m;
}

Mesh translated(const Mesh& m, float dx) {
  Mesh out = m;
  for (uint32_t v = 0; v < out.num_vertices(); ++v) out.positions[3 * size_t(v)] += dx;
  return out;
}

double mfne(const Mesh& clean, const std::vector<float>& result) {
  return mean_face_normal_error(clean.view(), result.data()).mean_radians;
}

// Frames 1..frames of `clean_at(t)` with noise seeded t, each filtered alone and in one stream.
struct Errors {
  std::vector<double> alone, stream;
};
template <class CleanAt>
Errors run_sequence(CleanAt clean_at, int frames, float temporal) {
  CpuEngine alone(2), stream(2);
  TemporalHistory history;
  stream.set_history(&history);
  Errors r;
  for (int t = 0; t < frames; ++t) {
    const Mesh& clean = clean_at(t);  // a reference or a temporary kept alive
    const Mesh input = noisy(clean, 100 + t);
    FrameResult a, s;
    EXPECT_TRUE(alone.process(input.view(), temporal_params(temporal), a).ok());
    EXPECT_TRUE(stream.process(input.view(), temporal_params(temporal), s).ok());
    r.alone.push_back(mfne(clean, a.positions));
    r.stream.push_back(mfne(clean, s.positions));
    if (t > 0) {
      EXPECT_GT(s.prior_coverage, 0.9f) << "frame " << t;
      EXPECT_FALSE(s.history_reset);
    }
  }
  EXPECT_EQ(history.frames, uint64_t(frames));
  EXPECT_EQ(history.resets, 0u);
  return r;
}

double mean_from(const std::vector<double>& v, size_t first) {
  return std::accumulate(v.begin() + first, v.end(), 0.0) / double(v.size() - first);
}

TEST(Temporal, AStillSurfaceGetsBetterThanEachFrameAlone) {
  const Mesh sphere = test::make_icosphere(4);
  const Errors r = run_sequence([&](int) -> const Mesh& { return sphere; }, 8, 0.75f);
  EXPECT_DOUBLE_EQ(r.stream[0], r.alone[0]) << "the first frame has no history";
  // Measured 0.80-0.87 of the per-frame error from the third frame on.
  EXPECT_LT(mean_from(r.stream, 3), 0.92 * mean_from(r.alone, 3));
}

TEST(Temporal, AMovingSurfaceIsNotMadeWorse) {
  // Half a mean edge a frame (the sphere's edges are about 0.08): a motion the history must
  // take out, not average in.
  const Mesh sphere = test::make_icosphere(4);
  const Errors r = run_sequence([&](int t) { return translated(sphere, 0.04f * float(t)); }, 8, 0.75f);
  for (size_t t = 1; t < r.stream.size(); ++t) EXPECT_LT(r.stream[t], 1.05 * r.alone[t]) << "frame " << t;
}

// `m` with its vertices renumbered by a permutation drawn from `seed` (and the triangles with
// them); perm[j] is the old id of new vertex j.
Mesh renumbered(const Mesh& m, uint32_t seed, std::vector<uint32_t>& perm) {
  perm.resize(m.num_vertices());
  std::iota(perm.begin(), perm.end(), 0u);
  std::shuffle(perm.begin(), perm.end(), std::mt19937(seed));
  std::vector<uint32_t> inverse(perm.size());
  for (uint32_t j = 0; j < perm.size(); ++j) inverse[perm[j]] = j;
  Mesh out = m;
  for (uint32_t j = 0; j < perm.size(); ++j)
    for (int c = 0; c < 3; ++c) out.positions[3 * size_t(j) + c] = m.positions[3 * size_t(perm[j]) + c];
  for (uint32_t& v : out.triangles) v = inverse[v];
  return out;
}

TEST(Temporal, VertexIdsPlayNoPartInTheSpatialTrack) {
  // The same frames with the vertices renumbered (and the triangles with them) in the second
  // frame: the result is the first run's, renumbered. The first frame is renumbered too, so
  // that neither second frame keeps its connectivity (which would take track A, ids).
  const Mesh sphere = test::make_icosphere(3);
  std::vector<uint32_t> perm0, perm;
  const Mesh f0 = renumbered(noisy(sphere, 1), 3, perm0), f1 = noisy(sphere, 2);
  const Mesh shuffled = renumbered(f1, 7, perm);

  FrameResult plain, renumbered_result;
  for (auto [frame, out] :
       {std::pair<const Mesh*, FrameResult*>{&f1, &plain}, {&shuffled, &renumbered_result}}) {
    CpuEngine e(1);
    TemporalHistory h;
    e.set_history(&h);
    FrameResult first;
    ASSERT_TRUE(e.process(f0.view(), temporal_params(0.75f), first).ok());
    ASSERT_TRUE(e.process(frame->view(), temporal_params(0.75f), *out).ok());
    EXPECT_EQ(out->temporal_track, TemporalTrack::kSpace);
    EXPECT_GT(out->prior_share, 0.1f) << "the history was used";
  }
  for (uint32_t j = 0; j < perm.size(); ++j)
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(renumbered_result.positions[3 * size_t(j) + c], plain.positions[3 * size_t(perm[j]) + c],
                  1e-4f)
          << "vertex " << j;
}

// The mean x component of a history's motion, in units of `dx`.
double mean_motion_x(const TemporalHistory& h, float dx) {
  double sum = 0.0;
  const size_t n = h.motion.size() / 3;
  for (size_t v = 0; v < n; ++v) sum += h.motion[3 * v];
  return sum / double(n) / double(dx);
}

// The mean x motion of a sphere moving dx a frame and renumbered every frame, as each frame's
// estimate found it (in units of dx), frames 1..5; `from_rest` drops the motion a frame found
// before the next (what the estimate does without the prediction).
std::vector<double> sphere_motion_found(float dx, bool from_rest) {
  const Mesh sphere = test::make_icosphere(4);
  CpuEngine stream(2);
  TemporalHistory history;
  stream.set_history(&history);
  std::vector<double> found;
  for (int t = 0; t < 6; ++t) {
    std::vector<uint32_t> perm;
    const Mesh frame = renumbered(noisy(translated(sphere, dx * float(t)), 20 + t), 30 + t, perm);
    FrameResult r;
    EXPECT_TRUE(stream.process(frame.view(), temporal_params(0.75f), r).ok());
    EXPECT_EQ(r.temporal_track, TemporalTrack::kSpace);
    if (t == 0) {
      EXPECT_TRUE(history.motion.empty()) << "a first frame finds no motion";
      continue;
    }
    EXPECT_EQ(history.motion.size(), history.positions.size());
    found.push_back(mean_motion_x(history, dx));
    if (from_rest) history.motion.clear();
  }
  return found;
}

TEST(Temporal, TheMotionAFrameFindsStartsTheNextFramesEstimate) {
  // A sphere moving 1.5 mean edges a frame (its edges are about 0.08), renumbered every frame
  // (track B); frame t maps onto frame t - 1 by -dx. A lookup finds the nearest point of the
  // last surface, along the normal, and a patch of a sphere sliding along itself is the sphere
  // turning about its centre, which no fit of the patch tells from rest (the aperture problem):
  // from rest each frame's estimate holds about 0.3 of the motion (measured -0.29 to -0.31 dx).
  // Started from the last frame's motion, each frame keeps what the last found and adds to it
  // (measured -0.29, -0.29, -0.32, -0.36, -0.41 dx).
  const float dx = 0.12f;
  const std::vector<double> found = sphere_motion_found(dx, false);
  const std::vector<double> rest = sphere_motion_found(dx, true);
  ASSERT_EQ(found.size(), 5u);
  ASSERT_EQ(rest.size(), 5u);
  EXPECT_LT(found.front(), -0.25) << "the motion's normal part, from rest";
  for (size_t k = 1; k < found.size(); ++k) {
    EXPECT_LT(found[k], found[k - 1] + 0.01) << "frame " << k + 1 << " keeps the last one's motion";
    EXPECT_GT(found[k], -1.05) << "frame " << k + 1 << " does not overshoot";
  }
  EXPECT_LT(found.back(), rest.back() - 0.05) << "five frames of prediction find more than one from rest";
  EXPECT_LT(found.back(), found.front() - 0.05) << "the estimate grows frame by frame";
}

// The step runs whole under a caller's expired token (parallel_for skips the chunks of one, and
// the step's serial code reads what its loops wrote): the same result as without one.
TEST(Temporal, TheStepRunsWholeUnderAnExpiredToken) {
  const Mesh sphere = test::make_icosphere(3);
  const Mesh f0 = noisy(sphere, 1), f1 = noisy(sphere, 2);
  double edge = 0.0;
  for (size_t t = 0; t < f0.triangles.size(); t += 3)
    for (int k = 0; k < 3; ++k) {
      const float* a = &f0.positions[3 * size_t(f0.triangles[t + k])];
      const float* b = &f0.positions[3 * size_t(f0.triangles[t + (k + 1) % 3])];
      edge += std::sqrt(double(a[0] - b[0]) * (a[0] - b[0]) + double(a[1] - b[1]) * (a[1] - b[1]) +
                        double(a[2] - b[2]) * (a[2] - b[2]));
    }
  edge /= double(f0.triangles.size());
  std::vector<float> results[2];
  TemporalStep steps[2];
  for (int expired = 0; expired < 2; ++expired) {
    TemporalHistory history;
    TemporalScratch scratch;
    std::vector<float> first = f0.positions;
    follow_history(f0.view(), first, edge, 0.2f, 0.75f, history, scratch, 2);
    results[expired] = f1.positions;
    std::atomic<bool> stop{expired == 1};
    const CancelToken token(&stop);
    const CancelScope scope(&token);
    steps[expired] = follow_history(f1.view(), results[expired], edge, 0.2f, 0.75f, history, scratch, 2);
  }
  EXPECT_GT(steps[0].share, 0.05f) << "the history was used";
  EXPECT_NE(results[0], f1.positions) << "the frame was pulled";
  EXPECT_EQ(steps[1].share, steps[0].share);
  EXPECT_EQ(results[1], results[0]);
}

TEST(Temporal, ASceneCutRestartsTheHistoryAndLeavesTheFrameAlone) {
  const Mesh sphere = test::make_icosphere(3);
  CpuEngine stream(1), alone(1);
  TemporalHistory history;
  stream.set_history(&history);
  FrameResult r;
  ASSERT_TRUE(stream.process(noisy(sphere, 1).view(), temporal_params(0.75f), r).ok());
  std::vector<uint32_t> order;  // the same place, renumbered: track B, which finds a motion
  ASSERT_TRUE(stream.process(renumbered(noisy(sphere, 3), 5, order).view(), temporal_params(0.75f), r).ok());
  EXPECT_EQ(history.motion.size(), history.positions.size());
  // Five diameters away, renumbered: with the connectivity kept, track A would read the jump
  // as a motion its ids follow (kernels/temporal_ids.h); the spatial track sees a cut.
  std::vector<uint32_t> perm;
  const Mesh elsewhere = renumbered(noisy(translated(sphere, 10.f), 2), 9, perm);
  FrameResult cut, single;
  ASSERT_TRUE(stream.process(elsewhere.view(), temporal_params(0.75f), cut).ok());
  ASSERT_TRUE(alone.process(elsewhere.view(), temporal_params(0.75f), single).ok());
  EXPECT_TRUE(cut.history_reset);
  EXPECT_EQ(cut.prior_coverage, 0.f);
  EXPECT_EQ(history.resets, 1u);
  EXPECT_EQ(history.frames, 1u) << "the cut frame starts the history again";
  EXPECT_TRUE(history.motion.empty()) << "a cut finds no motion for the next frame to start from";
  EXPECT_EQ(cut.positions, single.positions);
}

TEST(Temporal, ZeroIsEachFrameAloneAndKeepsNothing) {
  const Mesh sphere = test::make_icosphere(3);
  CpuEngine stream(1), alone(1);
  TemporalHistory history;
  stream.set_history(&history);
  for (uint64_t seed : {1, 2, 3}) {
    const Mesh frame = noisy(sphere, seed);
    FrameResult s, a;
    ASSERT_TRUE(stream.process(frame.view(), temporal_params(0.f), s).ok());
    ASSERT_TRUE(alone.process(frame.view(), temporal_params(0.f), a).ok());
    EXPECT_EQ(s.positions, a.positions);
  }
  EXPECT_TRUE(history.empty());
}

TEST(Temporal, OutOfRangeStrengthIsRejected) {
  CpuEngine e(1);
  FrameResult r;
  for (float bad : {-0.1f, 1.5f}) {
    const Status s = e.process(test::make_icosphere(2).view(), temporal_params(bad), r);
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument) << bad;
    EXPECT_NE(s.message().find("temporal"), std::string::npos) << s.message();
  }
}

}  // namespace
}  // namespace fq
