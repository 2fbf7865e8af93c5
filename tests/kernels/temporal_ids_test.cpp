// Track A of temporal filtering (kernels/temporal_ids.h): the input averaged through vertex ids
// when a stream keeps its connectivity, the ids checked against a smooth motion.
#include "kernels/temporal_ids.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <vector>

#include "eval/error_metrics.h"
#include "eval/noise.h"
#include "kernels/cpu_engine.h"
#include "kernels/frame_prep.h"
#include "kernels/temporal.h"
#include "kernels/temporal_math.h"
#include "tests/support/test_meshes.h"

namespace fq {
namespace {

Mesh noisy(const Mesh& clean, uint64_t seed, double sigma = 0.2) {
  Mesh m = clean;
  add_gaussian_noise(m, sigma, seed);
  return m;
}

double rms_to(const Mesh& clean, const float* p) {
  double sum = 0.0;
  for (size_t i = 0; i < clean.positions.size(); ++i)
    sum += (p[i] - clean.positions[i]) * (p[i] - clean.positions[i]);
  return std::sqrt(sum / clean.num_vertices());
}

// A frame's step against `track`; the scale is `like`'s mean edge (the engine takes the last
// result's: a frame whose ids are scrambled has scrambled edges).
IdStep step(const Mesh& frame, IdTrack& track, std::vector<float>& out, TemporalScratch& s,
            const Mesh* like = nullptr) {
  const double edge = mean_edge_length((like != nullptr ? *like : frame).view(), 2);
  return average_with_ids(frame.view(), connectivity_fingerprint(frame.view(), 2), edge, 0.75f, track, out, s,
                          2);
}

// `m` with the positions of the vertices `chosen` permuted among themselves (seed `seed`):
// the same triangles, ids that no longer follow the surface there.
Mesh scrambled(const Mesh& m, const std::vector<uint32_t>& chosen, uint32_t seed) {
  std::vector<uint32_t> perm = chosen;
  std::shuffle(perm.begin(), perm.end(), std::mt19937(seed));
  Mesh out = m;
  for (size_t i = 0; i < chosen.size(); ++i)
    for (int k = 0; k < 3; ++k)
      out.positions[3 * size_t(chosen[i]) + k] = m.positions[3 * size_t(perm[i]) + k];
  return out;
}

TEST(TemporalIds, FingerprintFollowsTheTrianglesNotThePositionsNorTheThreads) {
  const Mesh a = test::make_icosphere(3);
  const uint64_t h = connectivity_fingerprint(a.view(), 1);
  EXPECT_EQ(connectivity_fingerprint(a.view(), 4), h);
  EXPECT_EQ(connectivity_fingerprint(noisy(a, 3).view(), 2), h) << "positions play no part";
  Mesh b = a;
  std::swap(b.triangles[0], b.triangles[1]);  // one triangle's corners turned
  EXPECT_NE(connectivity_fingerprint(b.view(), 2), h);
  const Mesh c = test::make_icosphere(2);
  EXPECT_NE(connectivity_fingerprint(c.view(), 2), h);
}

TEST(TemporalIds, TheFirstFrameAndANewConnectivityRestartTheTrack) {
  const Mesh sphere = test::make_icosphere(3);
  IdTrack track;
  TemporalScratch s;
  std::vector<float> out;
  EXPECT_FALSE(step(sphere, track, out, s).ran);
  EXPECT_EQ(track.averaged, sphere.positions) << "the track starts from the raw frame";
  const Mesh other = test::make_icosphere(2);
  EXPECT_FALSE(step(other, track, out, s).ran);
  EXPECT_EQ(track.vertices, other.num_vertices());
  EXPECT_TRUE(step(noisy(other, 1), track, out, s).ran);
}

TEST(TemporalIds, ASmoothMotionPassesWhole) {
  // A rotation by 3 degrees and a shift of two mean edges: locally affine, so the ring means
  // take all of it and nothing is left to average (the averaged input is the new frame).
  const Mesh sphere = test::make_icosphere(4);
  Mesh moved = sphere;
  const float c = std::cos(0.05f), sn = std::sin(0.05f);
  for (uint32_t v = 0; v < moved.num_vertices(); ++v) {
    float* p = &moved.positions[3 * size_t(v)];
    const float x = p[0], y = p[1];
    p[0] = c * x - sn * y + 0.1f;
    p[1] = sn * x + c * y;
  }
  IdTrack track;
  TemporalScratch s;
  std::vector<float> out;
  step(sphere, track, out, s);
  const IdStep st = step(moved, track, out, s);
  ASSERT_TRUE(st.ran);
  EXPECT_LT(st.residual, 0.01f);
  EXPECT_LT(rms_to(moved, out.data()) / mean_edge_length(sphere.view(), 1), 0.01);
}

TEST(TemporalIds, AStillSurfaceAveragesItsNoiseOut) {
  const Mesh sphere = test::make_icosphere(4);
  IdTrack track;
  TemporalScratch s;
  std::vector<float> out;
  double raw = 0.0, averaged = 0.0;
  for (int t = 0; t < 12; ++t) {
    const Mesh frame = noisy(sphere, 50 + t);
    const IdStep st = step(frame, track, out, s);
    if (t < 6) continue;
    ASSERT_TRUE(st.ran);
    EXPECT_GT(st.share, 0.7f) << "noise alone is not gated";
    raw += rms_to(sphere, frame.positions.data());
    averaged += rms_to(sphere, out.data());
  }
  // Exponential averaging at 0.75 keeps (1 - s) / (1 + s) = 1/7 of the noise's variance in
  // theory (0.38 of its RMS); the motion's ring means let some through.
  EXPECT_LT(averaged, 0.6 * raw);
}

TEST(TemporalIds, IdsThatDoNotFollowTheSurfaceAreRefused) {
  // The same triangles, every position at another id: ids mean nothing.
  const Mesh sphere = test::make_icosphere(3);
  std::vector<uint32_t> all(sphere.num_vertices());
  std::iota(all.begin(), all.end(), 0u);
  const Mesh shuffled = scrambled(sphere, all, 5);
  IdTrack track;
  TemporalScratch s;
  std::vector<float> out;
  step(sphere, track, out, s);
  const IdStep st = step(shuffled, track, out, s, &sphere);
  EXPECT_FALSE(st.ran);
  EXPECT_TRUE(st.refused);
  EXPECT_GT(st.residual, kIdReach);
  EXPECT_EQ(track.averaged, shuffled.positions) << "the track restarts from the frame";
}

TEST(TemporalIds, WhereIdsStopFollowingTheSurfaceTheFrameIsLeftAlone) {
  // A cap's ids scrambled among themselves (a local tracking failure: each moves by a few mean
  // edges in no common direction) while the rest holds still.
  const Mesh sphere = test::make_icosphere(4);
  std::vector<uint32_t> cap;
  std::vector<bool> in_cap(sphere.num_vertices(), false);
  for (uint32_t v = 0; v < sphere.num_vertices(); ++v)
    if (sphere.positions[3 * size_t(v) + 2] > 0.9f) {
      cap.push_back(v);
      in_cap[v] = true;
    }
  ASSERT_GT(cap.size(), 50u);
  IdTrack track;
  TemporalScratch s;
  std::vector<float> out;
  const Mesh before = noisy(sphere, 1);
  step(before, track, out, s, &sphere);
  const Mesh frame = scrambled(noisy(sphere, 2), cap, 3);
  const IdStep st = step(frame, track, out, s, &sphere);
  ASSERT_TRUE(st.ran) << "a local failure does not refuse the frame";
  // How far each vertex went back towards the last input, as a share of the way there.
  double back_cap = 0.0, back_rest = 0.0;
  for (uint32_t v = 0; v < sphere.num_vertices(); ++v) {
    double moved = 0.0, way = 0.0;
    for (int k = 0; k < 3; ++k) {
      const size_t i = 3 * size_t(v) + k;
      moved += double(out[i] - frame.positions[i]) * (out[i] - frame.positions[i]);
      way += double(before.positions[i] - frame.positions[i]) * (before.positions[i] - frame.positions[i]);
    }
    (in_cap[v] ? back_cap : back_rest) += std::sqrt(moved / way);
  }
  back_cap /= double(cap.size());
  back_rest /= double(sphere.num_vertices() - cap.size());
  EXPECT_LT(back_cap, 0.15) << "scrambled ids are not averaged in";
  EXPECT_GT(back_rest, 0.5) << "the rest is averaged (0.75 of the non-smooth part)";
}

TEST(TemporalIds, NoisePartReadsHowMuchOfTheRestSurvivesARingMean) {
  EXPECT_FLOAT_EQ(noise_part(0.15f, 1.f, 0.15f), 1.f) << "white noise keeps its ring mean's share";
  EXPECT_FLOAT_EQ(noise_part(1.f, 1.f, 0.15f), 0.f) << "all of it survives: a missed motion";
  // Noise σ² = 1 and a missed motion e² = 1: q = (0.15 + 1) / 2, the noise's part 1/2.
  EXPECT_NEAR(noise_part(0.575f, 1.f, 0.15f), 0.5f, 1e-6f);
  EXPECT_FLOAT_EQ(noise_part(0.f, 0.f, 0.15f), 1.f) << "no rest, nothing to weigh";
}

TEST(TemporalIds, TheEngineTakesTrackAWhileTheConnectivityHoldsAndTrackBWhenItChanges) {
  const Mesh sphere = test::make_icosphere(3);
  CpuEngine e(2);
  TemporalHistory h;
  e.set_history(&h);
  Params p;
  p.filtering.temporal = 0.75f;
  FrameResult r;
  ASSERT_TRUE(e.process(noisy(sphere, 1).view(), p, r).ok());
  EXPECT_EQ(r.temporal_track, TemporalTrack::kSpace) << "a first frame: the spatial track keeps it";
  ASSERT_TRUE(e.process(noisy(sphere, 2).view(), p, r).ok());
  EXPECT_EQ(r.temporal_track, TemporalTrack::kIds);
  EXPECT_GT(r.prior_share, 0.7f);
  EXPECT_EQ(h.frames, 2u) << "an averaged frame's result is the spatial track's history too";
  Mesh turned = noisy(sphere, 3);
  std::swap(turned.triangles[0], turned.triangles[1]);
  ASSERT_TRUE(e.process(turned.view(), p, r).ok());
  EXPECT_EQ(r.temporal_track, TemporalTrack::kSpace);
  EXPECT_GT(r.prior_coverage, 0.9f) << "it follows the averaged frame's result";
  Params alone = p;
  alone.filtering.temporal = 0.f;
  ASSERT_TRUE(e.process(turned.view(), alone, r).ok());
  EXPECT_EQ(r.temporal_track, TemporalTrack::kNone);
}

TEST(TemporalIds, AveragedFramesBeatFramesAlone) {
  const Mesh sphere = test::make_icosphere(4);
  CpuEngine alone(2), stream(2);
  TemporalHistory h;
  stream.set_history(&h);
  Params p;
  p.filtering.temporal = 0.75f;
  double err_alone = 0.0, err_stream = 0.0;
  for (int t = 0; t < 8; ++t) {
    const Mesh frame = noisy(sphere, 200 + t);
    FrameResult a, s;
    ASSERT_TRUE(alone.process(frame.view(), p, a).ok());
    ASSERT_TRUE(stream.process(frame.view(), p, s).ok());
    if (t < 3) continue;
    err_alone += mean_face_normal_error(sphere.view(), a.positions.data()).mean_radians;
    err_stream += mean_face_normal_error(sphere.view(), s.positions.data()).mean_radians;
  }
  // Measured 0.87 (frames 3-7; the sphere has no detail to lose, its own noise estimate
  // already filters it well).
  EXPECT_LT(err_stream, 0.93 * err_alone);
}

}  // namespace
}  // namespace fq
