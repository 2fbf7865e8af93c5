// Track A of temporal filtering (kernels/temporal_ids.h): the input averaged through vertex ids
// when a stream keeps its connectivity, the ids checked against a smooth motion.
#include "kernels/temporal_ids.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <numeric>
#include <random>
#include <vector>

#include "eval/error_metrics.h"
#include "eval/noise.h"
#include "kernels/cpu_engine.h"
#include "kernels/frame_prep.h"
#include "kernels/rigid_motion.h"
#include "kernels/temporal.h"
#include "kernels/temporal_math.h"
#include "kernels/vertex_faces.h"
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

// `passes` ring means of a over the fan.
template <class T>
void fan_means(const FanView& fan, std::vector<T>& a, int passes) {
  std::vector<T> b(a.size());
  for (int p = 0; p < passes; ++p) {
    for (uint32_t v = 0; v < a.size(); ++v) b[v] = ring_mean(fan, a.data(), v);
    a.swap(b);
  }
}

// A mesh's fans (vertex -> triangles), kept with the view that reads them.
struct Fans {
  std::vector<uint32_t> offsets, faces;
  FanView view{};
  explicit Fans(const Mesh& m) {
    build_vertex_faces(m.triangles.data(), m.num_triangles(), m.num_vertices(), offsets, faces);
    view = FanView{m.triangles.data(), offsets.data(), faces.data()};
  }
  Fans(const Fans&) = delete;
  Fans& operator=(const Fans&) = delete;
};

// The difference p - clean per vertex, scaled by `unit`.
std::vector<Vec3> difference(const Mesh& clean, const float* p, double unit) {
  std::vector<Vec3> d(clean.num_vertices());
  for (uint32_t v = 0; v < d.size(); ++v)
    for (int k = 0; k < 3; ++k)
      (&d[v].x)[k] = float((p[3 * size_t(v) + k] - clean.positions[3 * size_t(v) + k]) * unit);
  return d;
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

// The engine's fingerprint of a frame compares the track's kept triangles instead of hashing
// them: always the frame's own hash, whether the triangles are the kept ones or not.
TEST(TemporalIds, FrameConnectivityIsTheFramesFingerprintWithOrWithoutTheTracksTables) {
  const Mesh sphere = test::make_icosphere(3);
  const uint64_t h = connectivity_fingerprint(sphere.view(), 1);
  IdTrack track;
  EXPECT_EQ(frame_connectivity(sphere.view(), track, 2), h) << "no tables yet: hashed";
  TemporalScratch s;
  std::vector<float> out;
  step(noisy(sphere, 1), track, out, s, &sphere);
  ASSERT_TRUE(step(noisy(sphere, 2), track, out, s, &sphere).ran);
  ASSERT_EQ(track.topology.fingerprint, h) << "the tables are held";
  EXPECT_EQ(frame_connectivity(noisy(sphere, 3).view(), track, 2), h);
  Mesh turned = sphere;  // the same counts, one triangle's corners turned
  std::rotate(turned.triangles.end() - 3, turned.triangles.end() - 2, turned.triangles.end());
  const uint64_t t = connectivity_fingerprint(turned.view(), 1);
  ASSERT_NE(t, h);
  EXPECT_EQ(frame_connectivity(turned.view(), track, 2), t);
  const Mesh smaller = test::make_icosphere(2);
  EXPECT_EQ(frame_connectivity(smaller.view(), track, 2), connectivity_fingerprint(smaller.view(), 1));
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

// `m` turned by `angle` in the plane of axes a and b, then shifted by `shift` along a.
Mesh turned(const Mesh& m, float angle, int a, int b, float shift) {
  Mesh out = m;
  const float c = std::cos(angle), sn = std::sin(angle);
  for (uint32_t v = 0; v < out.num_vertices(); ++v) {
    float* p = &out.positions[3 * size_t(v)];
    const float x = p[a], y = p[b];
    p[a] = c * x - sn * y + shift;
    p[b] = sn * x + c * y;
  }
  return out;
}

// A new track's step from `first` to `moved`, its averaged input in `out`.
IdStep second_step(const Mesh& first, const Mesh& moved, std::vector<float>& out) {
  IdTrack track;
  TemporalScratch s;
  step(first, track, out, s);
  return step(moved, track, out, s);
}

TEST(TemporalIds, ASmoothMotionPassesWhole) {
  // A rotation by 3 degrees and a shift of two mean edges: the ring means and their rigid fit
  // take all of it and nothing is left to average (the averaged input is the new frame).
  const Mesh sphere = test::make_icosphere(4);
  const Mesh moved = turned(sphere, 0.05f, 0, 1, 0.1f);
  std::vector<float> out;
  const IdStep st = second_step(sphere, moved, out);
  ASSERT_TRUE(st.ran);
  EXPECT_LT(st.residual, 0.01f);
  EXPECT_LT(rms_to(moved, out.data()) / mean_edge_length(sphere.view(), 1), 0.01);
}

TEST(TemporalIds, ARotationOfACurvedSurfacePassesWholeWithItsRigidFit) {
  // A small sphere (some five edges across) turned by 0.3 rad: the ring means of the
  // displacement are the rotation of points inside the sphere, not of the vertices, and leave a
  // rest that the average would take for noise. The rigid fit of each neighbourhood takes the
  // rotation whole, so the averaged input is the new frame.
  const Mesh sphere = test::make_icosphere(2);
  const Mesh moved = turned(sphere, 0.3f, 0, 2, 0.f);
  const double edge = mean_edge_length(sphere.view(), 1);
  // What the ring means alone leave of the displacement (mean edges, RMS).
  const Fans fans(sphere);
  const std::vector<Vec3> d = difference(sphere, moved.positions.data(), 1.0 / edge);
  std::vector<Vec3> m = d;
  fan_means(fans.view, m, kIdMotionPasses);
  double left = 0.0;
  for (uint32_t v = 0; v < d.size(); ++v) left += norm2(d[v] - m[v]);
  left = std::sqrt(left / d.size());
  ASSERT_GT(left, 0.05) << "the ring means alone miss part of the rotation";
  std::vector<float> out;
  const IdStep st = second_step(sphere, moved, out);
  ASSERT_TRUE(st.ran);
  EXPECT_LT(st.residual, 1e-3f);
  EXPECT_LT(rms_to(moved, out.data()) / edge, 1e-3) << "ring means alone left " << left;
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

TEST(TemporalIds, AYoungTrackWeighsItsFramesAlike) {
  // The mean of the k views until the recursive average's own weight is reached.
  EXPECT_FLOAT_EQ(history_weight(0.75f, 1), 0.5f);
  EXPECT_FLOAT_EQ(history_weight(0.75f, 2), 2.f / 3.f);
  EXPECT_FLOAT_EQ(history_weight(0.75f, 3), 0.75f);
  EXPECT_FLOAT_EQ(history_weight(0.75f, kIdFramesCounted), 0.75f);
  EXPECT_FLOAT_EQ(history_weight(0.4f, 1), 0.4f);
  EXPECT_FLOAT_EQ(history_weight(0.75f, 0), 0.f);
  // A still surface's second frame: the mean of the two keeps half the noise's variance.
  const Mesh sphere = test::make_icosphere(4);
  IdTrack track;
  TemporalScratch s;
  std::vector<float> out;
  const Mesh first = noisy(sphere, 60), second = noisy(sphere, 61);
  step(first, track, out, s);
  ASSERT_TRUE(step(second, track, out, s).ran);
  EXPECT_EQ(track.frames, 2u);
  const double raw = rms_to(sphere, second.positions.data());
  EXPECT_LT(rms_to(sphere, out.data()), 0.8 * raw) << "about 1/√2 of the noise, beside 0.79 at weight 0.75";
}

// The RMS of the band of p's error that the wide motion estimate takes from the narrow one:
// its narrow smooth part less its wide smooth part (kIdMotionPasses, then kIdWidePasses more
// ring means over the sphere), smooth over a few rings: what a viewer sees as the surface breathing.
double band_error(const Mesh& clean, const std::vector<float>& p) {
  const Fans fans(clean);
  const FanView& fan = fans.view;
  std::vector<Vec3> narrow = difference(clean, p.data(), 1.0);
  fan_means(fan, narrow, kIdMotionPasses);
  std::vector<Vec3> wide = narrow;
  fan_means(fan, wide, kIdWidePasses);
  double sum = 0.0;
  for (uint32_t v = 0; v < narrow.size(); ++v) sum += dot(narrow[v] - wide[v], narrow[v] - wide[v]);
  return std::sqrt(sum / double(narrow.size()));
}

TEST(TemporalIds, NoiseSmoothOverSeveralRingsIsAveragedWhereTheMotionIsSmooth) {
  // A still surface: the wide motion estimate holds, so the noise the narrow one would keep
  // as motion (smooth over four rings) is averaged out as well.
  const Mesh sphere = test::make_icosphere(5);
  IdTrack track;
  TemporalScratch s;
  std::vector<float> out;
  double raw = 0.0, averaged = 0.0, wide = 0.0;
  for (int t = 0; t < 12; ++t) {
    const Mesh frame = noisy(sphere, 80 + t);
    const IdStep st = step(frame, track, out, s);
    if (t < 6) continue;
    ASSERT_TRUE(st.ran);
    wide += st.wide / 6.0;
    raw += band_error(sphere, frame.positions);
    averaged += band_error(sphere, out);
  }
  EXPECT_GT(wide, 0.7) << "noise alone does not bend the motion";  // measured 0.80
  // Measured 0.56 of the raw frames' band, 0.64 with the narrow motion alone (0.52 with the
  // wide one taken whole everywhere).
  EXPECT_LT(averaged, 0.6 * raw);
}

TEST(TemporalIds, WhereTheMotionBendsTheNarrowEstimateFollowsIt) {
  // A wave travelling over the sphere, its wavelength some ten mean edges: smooth over a ring,
  // far from affine over eight. The wide estimate would flatten it, and the flattened part of
  // the wave would be averaged in as a lag; the share falls, and the frame keeps its wave.
  const Mesh sphere = test::make_icosphere(5);
  const double edge = mean_edge_length(sphere.view(), 2);
  const auto wave = [&](int t) {
    Mesh m = noisy(sphere, 90 + t, 0.05);
    for (uint32_t v = 0; v < m.num_vertices(); ++v) {
      float* p = &m.positions[3 * size_t(v)];
      const double phase = 2.0 * M_PI * (sphere.positions[3 * size_t(v)] / (10.0 * edge)) + 0.8 * t;
      p[2] += float(2.0 * edge * std::sin(phase));
    }
    return m;
  };
  IdTrack track;
  TemporalScratch s;
  std::vector<float> out;
  step(wave(0), track, out, s);
  const Mesh frame = wave(1);
  const IdStep st = step(frame, track, out, s);
  ASSERT_TRUE(st.ran);
  EXPECT_LT(st.wide, 0.3) << "the motion bends";  // measured under 0.03
  Mesh clean = frame;                             // the frame's wave without its noise
  for (uint32_t v = 0; v < clean.num_vertices(); ++v) {
    const double phase = 2.0 * M_PI * (sphere.positions[3 * size_t(v)] / (10.0 * edge)) + 0.8;
    for (int k = 0; k < 3; ++k) clean.positions[3 * size_t(v) + k] = sphere.positions[3 * size_t(v) + k];
    clean.positions[3 * size_t(v) + 2] += float(2.0 * edge * std::sin(phase));
  }
  // Measured 0.95 of the frame's error; 1.12 with the wide estimate taken whole.
  EXPECT_LT(rms_to(clean, out.data()), 1.05 * rms_to(clean, frame.positions.data())) << "no lag averaged in";
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
  EXPECT_GT(back_rest, 0.8 * history_weight(0.75f, 1))
      << "the rest is averaged (a second frame's weight, 1/2, of the non-smooth part)";
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
  EXPECT_GT(r.prior_share, 0.9f * history_weight(0.75f, 1));
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

// Track A leaves the history's normals pending; track B, on the frame after, follows the
// normals an eager computation gives: the same result as from a history whose normals were
// computed at once from the averaged frame's result.
TEST(TemporalIds, TrackBFollowsTheNormalsTrackALeftPending) {
  const Mesh sphere = test::make_icosphere(3);
  Params p;
  p.filtering.temporal = 0.75f;
  CpuEngine e(2);
  TemporalHistory lazy;
  e.set_history(&lazy);
  FrameResult r;
  ASSERT_TRUE(e.process(noisy(sphere, 1).view(), p, r).ok());
  ASSERT_TRUE(e.process(noisy(sphere, 2).view(), p, r).ok());
  ASSERT_EQ(r.temporal_track, TemporalTrack::kIds);
  ASSERT_TRUE(lazy.normals.empty());
  // The same history with its normals computed from the result over the sphere's fans.
  TemporalHistory eager = lazy;
  TemporalHistory orphan = lazy;
  std::vector<uint32_t> vf_offsets, vf_faces;
  build_vertex_faces(sphere.triangles.data(), sphere.num_triangles(), sphere.num_vertices(), vf_offsets,
                     vf_faces);
  TemporalScratch s;
  keep_as_history(FanView{sphere.triangles.data(), vf_offsets.data(), vf_faces.data()}, sphere.num_vertices(),
                  r.positions, r.mean_edge, eager, s, 2);
  Mesh turned = noisy(sphere, 3);
  std::swap(turned.triangles[0], turned.triangles[1]);
  FrameResult from_lazy, from_eager;
  ASSERT_TRUE(e.process(turned.view(), p, from_lazy).ok());
  e.set_history(&eager);
  ASSERT_TRUE(e.process(turned.view(), p, from_eager).ok());
  EXPECT_EQ(from_lazy.temporal_track, TemporalTrack::kSpace);
  EXPECT_GT(from_lazy.prior_share, 0.1f) << "it followed the history";
  EXPECT_EQ(from_lazy.positions, from_eager.positions);
  // A history whose connectivity the track no longer holds is not followed on stale tables.
  orphan.ids.topology.clear();
  settle_history_normals(orphan, s, 2);
  EXPECT_TRUE(orphan.empty());
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

// The step as it was written before its loops were fused and its connectivity kept: one loop
// per quantity, every table built from the frame, the ring means over the fan. The step must
// give its bytes for any thread count.
struct Reference {
  std::vector<float> averaged;  // the track's
  uint32_t frames = 1;          // the frames in it
  float share = 0.f, residual = 0.f, wide = 0.f;
};

// The sum of the squared weights of v's ring mean over the fan: v once, each other corner of
// each of its triangles once.
float fan_white(const FanView& fan, uint32_t v) {
  std::vector<uint32_t> corners;
  for (uint32_t k = fan.vf_offsets[v]; k < fan.vf_offsets[v + 1]; ++k)
    for (int c = 0; c < 3; ++c) {
      const uint32_t w = fan.tris[3 * size_t(fan.vf_faces[k]) + c];
      if (w != v) corners.push_back(w);
    }
  float count = 1.f, squares = 1.f;
  for (uint32_t c : corners) {
    count += 1.f;
    for (uint32_t d : corners) squares += c == d ? 1.f : 0.f;
  }
  return squares / (count * count);
}

float median_of(std::vector<float> values) {
  const auto mid = values.begin() + values.size() / 2;
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

// RigidInputs' twelve floats, summed and scaled lane by lane as the step's ring means sum them.
struct Lanes {
  float f[12];
};
Lanes operator+(const Lanes& a, const Lanes& b) {
  Lanes out;
  for (int k = 0; k < 12; ++k) out.f[k] = a.f[k] + b.f[k];
  return out;
}
Lanes operator*(float s, const Lanes& a) {
  Lanes out;
  for (int k = 0; k < 12; ++k) out.f[k] = s * a.f[k];
  return out;
}
RigidInputs inputs_of(const Lanes& l) {
  return {Point4{l.f[0], l.f[1], l.f[2], l.f[3]}, Point4{l.f[4], l.f[5], l.f[6], l.f[7]},
          Point4{l.f[8], l.f[9], l.f[10], l.f[11]}};
}

// The rest of `offset` after its narrow motion (in place), the wide motion's difference from
// the narrow one, and the local levels of both, over the fan. With `position` (the last averaged
// positions from the frame's origin, mean edges) each motion has its rigid correction.
void reference_parts(const FanView& fan, std::vector<Vec3>& offset, std::vector<Vec3>& wide,
                     std::vector<float>& level, std::vector<float>& wide_level,
                     const std::vector<Vec3>* position = nullptr) {
  const size_t n = offset.size();
  std::vector<Vec3> motion = offset;
  fan_means(fan, motion, kIdMotionPasses);
  std::vector<Lanes> lanes(n);
  std::vector<Vec3> narrow(n, Vec3{0.f, 0.f, 0.f});
  if (position != nullptr) {
    for (uint32_t v = 0; v < n; ++v) {
      const RigidInputs in = rigid_inputs((*position)[v], offset[v]);
      lanes[v] = Lanes{{in.p.x, in.p.y, in.p.z, in.p.w, in.q0.x, in.q0.y, in.q0.z, in.q0.w, in.q1.x, in.q1.y,
                        in.q1.z, in.q1.w}};
    }
    fan_means(fan, lanes, kIdMotionPasses);
    for (uint32_t v = 0; v < n; ++v)
      narrow[v] = rigid_correction(inputs_of(lanes[v]), motion[v], (*position)[v]);
  }
  wide = motion;
  fan_means(fan, wide, kIdWidePasses);
  if (position != nullptr) fan_means(fan, lanes, kIdWidePasses);
  level.resize(n);
  wide_level.resize(n);
  for (uint32_t v = 0; v < n; ++v) {
    const Vec3 c = position != nullptr ? rigid_correction(inputs_of(lanes[v]), wide[v], (*position)[v])
                                       : Vec3{0.f, 0.f, 0.f};
    offset[v] = offset[v] - (motion[v] + narrow[v]);
    wide[v] = (wide[v] + c) - (motion[v] + narrow[v]);
    level[v] = dot(offset[v], offset[v]);
    wide_level[v] = dot(wide[v], wide[v]);
  }
  fan_means(fan, level, kIdAgreementPasses);
  fan_means(fan, wide_level, kIdAgreementPasses);
}

// One step of `frame` against r.averaged (the averaged input of the frame before), loop by loop.
bool reference_step(const Mesh& frame, double mean_edge, float strength, Reference& r) {
  const uint32_t n = frame.num_vertices();
  std::vector<uint32_t> vf_offsets, vf_faces;
  build_vertex_faces(frame.triangles.data(), frame.num_triangles(), n, vf_offsets, vf_faces);
  const FanView fan{frame.triangles.data(), vf_offsets.data(), vf_faces.data()};
  std::vector<Vec3> wide;
  std::vector<float> level, wide_level;
  // What white noise leaves in the wide difference per unit of the narrow rest.
  std::vector<Vec3> probe(n);
  for (uint32_t v = 0; v < n; ++v) probe[v] = white_probe(v);
  reference_parts(fan, probe, wide, level, wide_level);
  const float wide_white = median_of(wide_level) / median_of(level);
  const float unit = float(1.0 / mean_edge);
  const float* x = frame.positions.data();
  std::vector<Vec3> offset(n), position(n);
  const Vec3 o = id_origin(frame.view(), 2);
  for (uint32_t v = 0; v < n; ++v) {
    const float* a = &r.averaged[3 * size_t(v)];
    offset[v] =
        unit * Vec3{x[3 * size_t(v)] - a[0], x[3 * size_t(v) + 1] - a[1], x[3 * size_t(v) + 2] - a[2]};
    position[v] = unit * Vec3{a[0] - o.x, a[1] - o.y, a[2] - o.z};
  }
  reference_parts(fan, offset, wide, level, wide_level, &position);
  std::vector<float> coherent(n), white(n);
  for (uint32_t v = 0; v < n; ++v) {
    const Vec3 c = ring_mean(fan, offset.data(), v);
    coherent[v] = dot(c, c);
    white[v] = fan_white(fan, v);
  }
  fan_means(fan, coherent, kIdAgreementPasses);
  fan_means(fan, white, kIdAgreementPasses);
  const float typical = median_of(level);
  r.residual = std::sqrt(typical);
  if (!ids_follow(typical)) return false;
  const float weight = history_weight(strength, r.frames++);
  double total = 0.0, wide_total = 0.0;
  for (uint32_t v = 0; v < n; ++v) {
    const float noise = noise_part(coherent[v], level[v], white[v]);
    const float share = id_share(level[v], typical, weight) * noise;
    const float g = wide_share(wide_level[v], wide_white * noise * level[v]);
    const Vec3 back = (share * float(mean_edge)) * (offset[v] - g * wide[v]);
    for (int k = 0; k < 3; ++k) r.averaged[3 * size_t(v) + k] = x[3 * size_t(v) + k] - (&back.x)[k];
    total += share;
    wide_total += g;
  }
  r.share = float(total / n);
  r.wide = float(wide_total / n);
  return true;
}

bool same_bytes(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

bool same_bits(float a, float b) { return std::bit_cast<uint32_t>(a) == std::bit_cast<uint32_t>(b); }

// A sphere turning and swelling a little from frame to frame, with fresh noise each frame.
Mesh moving_frame(const Mesh& sphere, int t) {
  Mesh m = noisy(sphere, 300 + t);
  const float angle = 0.02f * t, c = std::cos(angle), sn = std::sin(angle), scale = 1.f + 0.01f * t;
  for (uint32_t v = 0; v < m.num_vertices(); ++v) {
    float* p = &m.positions[3 * size_t(v)];
    const float x = p[0], y = p[1];
    p[0] = scale * (c * x - sn * y);
    p[1] = scale * (sn * x + c * y);
  }
  return m;
}

TEST(TemporalIds, TheStepGivesTheBytesOfItsLoopByLoopFormForAnyThreadCount) {
  // 10242 vertices: several ranges of kVertexGrain, so four threads do split the loops.
  const Mesh sphere = test::make_icosphere(5);
  const double edge = mean_edge_length(sphere.view(), 2);
  for (int threads : {1, 4}) {
    IdTrack track;
    TemporalScratch s;
    TemporalHistory history;
    std::vector<float> out;
    Reference ref;
    for (int t = 0; t < 5; ++t) {
      const Mesh frame = moving_frame(sphere, t);
      const IdStep st = average_with_ids(frame.view(), connectivity_fingerprint(frame.view(), threads), edge,
                                         0.75f, history.ids, out, s, threads);
      if (t == 0) {
        ASSERT_FALSE(st.ran);
        ref.averaged = frame.positions;
        continue;
      }
      ASSERT_TRUE(reference_step(frame, edge, 0.75f, ref));
      ASSERT_TRUE(st.ran) << "frame " << t;
      EXPECT_TRUE(same_bytes(out, ref.averaged)) << "frame " << t << ", " << threads << " threads";
      EXPECT_TRUE(same_bytes(history.ids.averaged, ref.averaged)) << "the track keeps the averaged input";
      EXPECT_TRUE(same_bits(st.share, ref.share)) << "frame " << t;
      EXPECT_TRUE(same_bits(st.residual, ref.residual)) << "frame " << t;
      EXPECT_TRUE(same_bits(st.wide, ref.wide)) << "frame " << t;
      // The result (here the averaged input) becomes the spatial track's history, its normals
      // pending until track B reads them; then those vertex_normal gives over the frame's fans.
      keep_averaged_result(frame.view(), out, edge, history);
      EXPECT_TRUE(history.normals.empty()) << "pending";
      EXPECT_EQ(history.normals_pending, history.ids.topology.fingerprint);
      settle_history_normals(history, s, threads);
      EXPECT_EQ(history.normals_pending, 0u);
      std::vector<uint32_t> vf_offsets, vf_faces;
      build_vertex_faces(frame.triangles.data(), frame.num_triangles(), frame.num_vertices(), vf_offsets,
                         vf_faces);
      const FanView fan{frame.triangles.data(), vf_offsets.data(), vf_faces.data()};
      std::vector<Vec3> x(frame.num_vertices());
      for (uint32_t v = 0; v < x.size(); ++v)
        x[v] = {out[3 * size_t(v)], out[3 * size_t(v) + 1], out[3 * size_t(v) + 2]};
      std::vector<float> normals;
      for (uint32_t v = 0; v < x.size(); ++v) {
        const Vec3 u = vertex_normal(fan, x.data(), v);
        normals.insert(normals.end(), {u.x, u.y, u.z});
      }
      EXPECT_TRUE(same_bytes(history.normals, normals)) << "frame " << t;
      EXPECT_TRUE(same_bytes(history.positions, out)) << "frame " << t;
    }
  }
}

TEST(TemporalIds, ANewConnectivityOfTheSameSizeRebuildsWhatTheTrackKeeps) {
  // Frames of one connectivity, then of another with the same vertex and triangle counts (one
  // edge flipped): the track's tables must be the new ones, as on a track that saw only those.
  const Mesh sphere = test::make_icosphere(4);
  Mesh flipped = sphere;
  {  // the two triangles on the edge (a, b) of triangle 0 become the two on the other diagonal
    const uint32_t a = flipped.triangles[0], b = flipped.triangles[1], c = flipped.triangles[2];
    for (uint32_t f = 1; f < flipped.num_triangles(); ++f) {
      uint32_t* t = &flipped.triangles[3 * size_t(f)];
      for (int k = 0; k < 3; ++k)
        if (t[k] == b && t[(k + 1) % 3] == a) {
          const uint32_t d = t[(k + 2) % 3];
          const uint32_t first[3] = {a, d, c}, second[3] = {d, b, c};
          std::copy(first, first + 3, flipped.triangles.begin());
          std::copy(second, second + 3, t);
          f = flipped.num_triangles();
          break;
        }
    }
  }
  ASSERT_NE(connectivity_fingerprint(flipped.view(), 1), connectivity_fingerprint(sphere.view(), 1));
  const auto frame_of = [](const Mesh& shape, int t) {
    Mesh m = shape;
    add_gaussian_noise(m, 0.2, 400 + t);
    return m;
  };
  IdTrack seen, fresh;
  TemporalScratch s1, s2;
  std::vector<float> out1, out2;
  for (int t = 0; t < 3; ++t) step(frame_of(sphere, t), seen, out1, s1, &sphere);
  for (int t = 3; t < 6; ++t) {
    const IdStep a = step(frame_of(flipped, t), seen, out1, s1, &sphere);
    const IdStep b = step(frame_of(flipped, t), fresh, out2, s2, &sphere);
    ASSERT_EQ(a.ran, b.ran) << "frame " << t;
    if (a.ran) {
      EXPECT_TRUE(same_bytes(out1, out2)) << "frame " << t;
    }
  }
  EXPECT_TRUE(same_bytes(seen.averaged, fresh.averaged));
}

}  // namespace
}  // namespace fq
