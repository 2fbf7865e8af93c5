// "qf+" (kernels/refine_math.h, refine_plan.h) on cases whose answer is known by hand: a
// cube's crease stays sharp, a clean plane does not move, the tangential moves stay in the
// filtered plane and along creases, the result follows the noise continuously and
// monotonically, and the whole method gives the same bits for any thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "eval/error_metrics.h"
#include "eval/noise.h"
#include "io/mesh_io.h"
#include "kernels/cpu_engine.h"
#include "kernels/frame_prep.h"
#include "kernels/refine_math.h"
#include "kernels/refine_plan.h"
#include "tests/support/test_meshes.h"

namespace fq {
namespace {

/// Positions and vertex -> triangle CSR of a mesh, as the engines hold them.
struct Fan {
  std::vector<Vec3> x;
  std::vector<uint32_t> offsets, faces;
  std::vector<uint32_t> tris;
  FanView view() const { return {tris.data(), offsets.data(), faces.data()}; }
};

Fan fan_of(const Mesh& m) {
  Fan f;
  f.tris = m.triangles;
  for (uint32_t v = 0; v < m.num_vertices(); ++v) f.x.push_back(test::vertex(m, v));
  f.offsets.assign(m.num_vertices() + 1, 0);
  for (uint32_t v : m.triangles) ++f.offsets[v + 1];
  for (size_t i = 1; i < f.offsets.size(); ++i) f.offsets[i] += f.offsets[i - 1];
  f.faces.resize(m.triangles.size());
  std::vector<uint32_t> cursor(f.offsets.begin(), f.offsets.end() - 1);
  for (uint32_t t = 0; t < m.num_triangles(); ++t)
    for (int k = 0; k < 3; ++k) f.faces[cursor[m.triangles[3 * t + k]]++] = t;
  return f;
}

// The vertex update's tangential move alone: updated_vertex with the whole share and no
// filtered plane to move onto (zero normals).
Vec3 share_move(const Fan& f, uint32_t v, const FreeDirections& dirs) {
  const std::vector<Vec3> no_planes(f.tris.size() / 3, Vec3{0.f, 0.f, 0.f});
  return updated_vertex(f.view(), f.x.data(), no_planes.data(), v, dirs, 1.f) - f.x[v];
}

Vec3 normal_of(const Fan& f, uint32_t t) {
  const uint32_t* tri = &f.tris[3 * size_t(t)];
  return triangle_geom(f.x[tri[0]], f.x[tri[1]], f.x[tri[2]]).normal;
}

TEST(KernelRefine, NormalFilterKeepsTheCubesCreaseSharp) {
  Fan f = fan_of(test::make_cube(4));
  const uint32_t m = static_cast<uint32_t>(f.tris.size() / 3);
  std::vector<TriangleGeom> geom(m);
  std::vector<Vec3> n(m), next(m);
  for (uint32_t t = 0; t < m; ++t)
    n[t] = (geom[t] = triangle_geom(f.x[f.tris[3 * size_t(t)]], f.x[f.tris[3 * size_t(t) + 1]],
                                    f.x[f.tris[3 * size_t(t) + 2]]))
               .normal;
  const Gaussian gs = Gaussian::with_sigma(0.5f), gr = Gaussian::with_sigma(0.35f);
  for (int it = 0; it < 3; ++it) {
    for (uint32_t t = 0; t < m; ++t)
      next[t] = filtered_face_normal(f.view(), geom.data(), n.data(), t, gs, gr);
    n.swap(next);
  }
  // Faces across a crease differ by |n_i - n_j|^2 = 2: weight exp(-2 / (2 0.35^2)) = 3e-4 of
  // a same-side face, so every normal stays within a few 1e-4 of its axis.
  for (uint32_t t = 0; t < m; ++t) {
    const Vec3 a = geom[t].normal;
    EXPECT_GT(dot(a, n[t]), 1.f - 1e-6f) << "triangle " << t;
  }
  // And the vertex update then leaves the clean cube where it is.
  for (uint32_t v = 0; v < f.x.size(); ++v) {
    const Vec3 p = normal_driven_position(f.view(), f.x.data(), n.data(), v);
    EXPECT_LT(std::sqrt(norm2(p - f.x[v])), 1e-3f) << "vertex " << v;
  }
}

TEST(KernelRefine, CleanPlaneDoesNotMove) {
  const Mesh plane = test::make_plane_grid(8, 8, 0.5f);
  Params p;  // the default method is qf+
  ASSERT_EQ(p.filtering.method, FilterMethod::kQuadricRefined);
  CpuEngine engine(2);
  FrameResult out;
  ASSERT_TRUE(engine.process(plane.view(), p, out).ok());
  EXPECT_LT(test::max_displacement(plane.positions, out.positions), 1e-5);
  EXPECT_EQ(out.noise_estimate, 0.f);
}

// A clean curved surface: the estimate finds almost no noise, so the filter barely touches it
// (no switch: the same passes run, with a range that lets no normal change).
TEST(KernelRefine, CleanIcosphereKeepsItsNormals) {
  const Mesh sphere = test::make_icosphere(4);
  CpuEngine engine(2);
  FrameResult out;
  ASSERT_TRUE(engine.process(sphere.view(), Params{}, out).ok());
  EXPECT_LT(out.noise_estimate, 0.01f);
  const double e = mean_face_normal_error(sphere.view(), out.positions.data()).mean_radians;
  EXPECT_LT(e, 0.002);  // 0.1 degree
}

TEST(KernelRefine, FractionalPassesCountTheirShare) {
  EXPECT_EQ(passes_of(0.f).count, 0);
  const Passes one = passes_of(1.f);
  EXPECT_EQ(one.count, 1);
  EXPECT_FLOAT_EQ(one.last, 1.f);
  const Passes p = passes_of(2.25f);
  EXPECT_EQ(p.count, 3);
  EXPECT_FLOAT_EQ(p.last, 0.25f);
  const Vec3 a{0.f, 0.f, 1.f}, b{1.f, 0.f, 0.f};
  EXPECT_FLOAT_EQ(partial_position(a, b, 0.25f).x, 0.25f);
  EXPECT_EQ(partial_position(a, b, 1.f).x, 1.f);
  const Vec3 n = partial_normal(a, b, 0.5f);  // halfway, renormalized: 45 degrees
  EXPECT_NEAR(n.x, std::sqrt(0.5f), 1e-6f);
  EXPECT_NEAR(n.z, std::sqrt(0.5f), 1e-6f);
}

// The plan grows with the noise in every pass count and in the range, from a light touch at 0.
TEST(KernelRefine, PlanGrowsWithTheNoise) {
  RefineParams r;
  const RefinePlan clean = plan_refinement(r, 0.f);
  EXPECT_EQ(clean.noise, 0.f);
  EXPECT_EQ(clean.rounds.count, 1);
  EXPECT_EQ(clean.tangential_allowance, 0.f);
  EXPECT_EQ(clean.tangential_step, 0.f);  // nothing to repair on a clean frame
  float last_rounds = 0.f, last_passes = 0.f, last_range = 0.f;
  for (float s : {0.02f, 0.05f, 0.1f, 0.2f, 0.3f, 0.5f}) {
    const RefinePlan p = plan_refinement(r, s);
    const float rounds = p.rounds.count - 1 + p.rounds.last;
    const float passes = p.normal_passes.count - 1 + p.normal_passes.last;
    const float range = -1.f / p.gr.neg_inv_two_sigma2;
    EXPECT_GE(rounds, last_rounds);
    EXPECT_GT(passes, last_passes);
    EXPECT_GT(range, last_range);
    last_rounds = rounds;
    last_passes = passes;
    last_range = range;
  }
  r.known_noise = 0.3f;  // a given noise wins over the estimate
  EXPECT_FLOAT_EQ(plan_refinement(r, 0.01f).noise, 0.3f);
  r.strength = 2.f;
  EXPECT_FLOAT_EQ(plan_refinement(r, 0.01f).noise, 0.6f);
}

// The tangential limit: a move within the allowance stays, a larger one shrinks to the
// allowance's share of its energy.
TEST(KernelRefine, TangentialMovesBeyondTheNoiseAreCutBack) {
  const Vec3 out{1.f, 2.f, 3.f}, t{0.2f, 0.f, 0.f};
  EXPECT_EQ(limited_position(out, t, 0.04f, 0.05f).x, 1.f);  // within: kept
  const Vec3 half = limited_position(out, t, 0.1f, 0.05f);   // twice the allowance: half kept
  EXPECT_NEAR(half.x, 1.f - 0.1f, 1e-6f);
  EXPECT_EQ(half.y, 2.f);
  EXPECT_NEAR(limited_position(out, t, 0.1f, 0.f).x, 0.8f, 1e-6f);  // no allowance: all of it undone
  // An allowance rounded below zero where nothing slid (a raw scan's boundary vertex): the
  // vertex stays where it is, finite.
  const Vec3 still = limited_position(out, Vec3{0.f, 0.f, 0.f}, 0.f, -1.5e-8f);
  EXPECT_EQ(still.x, 1.f);
  EXPECT_EQ(still.y, 2.f);
}

// How far the filter turned a vertex's triangles, by hand on one triangle: untouched 0, turned
// by θ (1 − cos θ)/2, flipped 1, collapsed (no normal) 1/2.
TEST(KernelRefine, FaceTurnMeasuresHowFarTrianglesTurned) {
  const Mesh tri = test::make_single_triangle();
  const Fan f = fan_of(tri);
  std::vector<Point4> in;
  for (const Vec3& x : f.x) in.push_back({x.x, x.y, x.z, 0.f});
  EXPECT_FLOAT_EQ(face_turn(f.view(), in.data(), f.x.data(), 0), 0.f);
  // Rotate the triangle by θ about an axis in its plane: every vertex sees the same turn.
  const Vec3 n = normal_of(f, 0);
  const Vec3 axis = normalized_or_zero(f.x[1] - f.x[0]);
  const float theta = 0.3f;
  std::vector<Vec3> turned = f.x;
  for (Vec3& x : turned) {  // Rodrigues about `axis` through x[0]
    const Vec3 r = x - f.x[0];
    x = f.x[0] + std::cos(theta) * r + std::sin(theta) * cross(axis, r) +
        (1.f - std::cos(theta)) * dot(axis, r) * axis;
  }
  for (uint32_t v = 0; v < 3; ++v)
    EXPECT_NEAR(face_turn(f.view(), in.data(), turned.data(), v), 0.5f * (1.f - std::cos(theta)), 1e-6f);
  ASSERT_GT(norm2(n), 0.5f);
  std::vector<Vec3> flipped = f.x;
  std::swap(flipped[1], flipped[2]);  // the same triangle wound the other way
  EXPECT_NEAR(face_turn(f.view(), in.data(), flipped.data(), 0), 1.f, 1e-6f);
  const std::vector<Vec3> collapsed(3, f.x[0]);
  EXPECT_FLOAT_EQ(face_turn(f.view(), in.data(), collapsed.data(), 0), 0.5f);
}

// The slide a vertex keeps follows the harm the noise did to its triangles: a vertex pushed so
// far sideways that its triangles flipped slides back and unflips them; one pushed less far, on
// the same flat plane (an irregular triangulation, nothing the normals show), stays where it is
// (a slide there would only make textures swim).
TEST(KernelRefine, SlidesRepairFlippedTrianglesAndLeaveIrregularOnesAlone) {
  Params p;
  p.filtering.refine.known_noise = 0.2f;
  CpuEngine engine(2);
  const uint32_t centre = 4 * 10 + 5;  // (5, 4), inside a grid of 9 x 9 cells
  auto run = [&](float push, std::vector<float>& moved, FrameResult& out) {
    Mesh plane = test::make_plane_grid(9, 9, 1.f);
    plane.positions[3 * size_t(centre)] += push;
    moved = plane.positions;
    ASSERT_TRUE(engine.process(plane.view(), p, out).ok());
  };
  std::vector<float> irregular;
  FrameResult kept;
  run(0.4f, irregular, kept);
  EXPECT_LT(test::max_displacement(irregular, kept.positions), 1e-4);

  std::vector<float> folded;
  FrameResult repaired;
  run(1.4f, folded, repaired);
  Mesh before = test::make_plane_grid(9, 9, 1.f);
  before.positions = folded;
  int flipped_before = 0, flipped_after = 0;
  for (uint32_t t = 0; t < before.num_triangles(); ++t) {
    const uint32_t* tri = &before.triangles[3 * size_t(t)];
    auto z_of = [&](const std::vector<float>& x) {
      const Vec3 a = test::vertex(x, tri[0]), b = test::vertex(x, tri[1]), c = test::vertex(x, tri[2]);
      return cross(b - a, c - a).z;
    };
    flipped_before += z_of(folded) < 0.f;
    flipped_after += z_of(repaired.positions) < 0.f;
  }
  EXPECT_GT(flipped_before, 0);
  EXPECT_EQ(flipped_after, 0);
  EXPECT_LT(std::fabs(repaired.positions[3 * size_t(centre)] - 5.f), 0.7f);  // back towards its grid place
}

// On a flat grid whose filtered normals are the plane's, the vertex update's tangential
// move takes a vertex pushed sideways back toward its 1-ring mean and never off the plane;
// a boundary vertex gets none.
TEST(KernelRefine, TangentialMoveStaysInTheFilteredPlane) {
  Fan f = fan_of(test::make_plane_grid(4, 4));
  const uint32_t centre = 12;  // (2, 2)
  ASSERT_NEAR(f.x[centre].x, 2.f, 1e-6f);
  ASSERT_NEAR(f.x[centre].y, 2.f, 1e-6f);
  f.x[centre] = Vec3{2.3f, 1.8f, 0.f};
  const std::vector<Vec3> up(f.tris.size() / 3, Vec3{0.f, 0.f, 1.f});
  const FreeDirections dirs = free_directions(f.view(), up.data(), centre, closed_fan(f.view(), centre));
  const Vec3 d = share_move(f, centre, dirs);
  EXPECT_EQ(d.z, 0.f);
  EXPECT_LT(d.x, 0.f);  // back toward x = 2
  EXPECT_GT(d.y, 0.f);  // and y = 2
  const Vec3 p = updated_vertex(f.view(), f.x.data(), up.data(), centre, dirs, 0.5f);
  EXPECT_EQ(p.z, 0.f);
  EXPECT_NEAR(p.x, f.x[centre].x + 0.5f * d.x, 1e-6f);
  const Vec3 none = share_move(f, 0, free_directions(f.view(), up.data(), 0, closed_fan(f.view(), 0)));
  EXPECT_EQ(norm2(none), 0.f);
}

// On a cube edge whose filtered normals are the two faces', the tangential move keeps only
// its part along the edge: moving across toward the 1-ring mean would round the crease (the
// move within the plane normal to the faces' mean normal did). At a corner it is zero.
TEST(KernelRefine, TangentialMoveRunsAlongACreaseOnly) {
  Fan f = fan_of(test::make_cube(4));
  std::vector<Vec3> faces(f.tris.size() / 3);
  for (uint32_t t = 0; t < faces.size(); ++t) faces[t] = normal_of(f, t);
  uint32_t v = 0;
  for (; v < f.x.size(); ++v) {
    const Vec3 p = f.x[v];
    if (p.x == 1.f && p.y == 1.f && std::fabs(p.z) < 0.9f) break;
  }
  ASSERT_LT(v, f.x.size());
  ASSERT_TRUE(closed_fan(f.view(), v));
  f.x[v] = f.x[v] + Vec3{-0.1f, 0.f, 0.2f};  // off the edge into the face y = 1, and along it
  const Vec3 d = share_move(f, v, free_directions(f.view(), faces.data(), v, true));
  EXPECT_NEAR(d.x, 0.f, 1e-6f);
  EXPECT_NEAR(d.y, 0.f, 1e-6f);
  EXPECT_LT(d.z, -0.05f);  // back toward the middle of its ring along the edge
  uint32_t corner = 0;
  for (; corner < f.x.size(); ++corner) {
    const Vec3 p = f.x[corner];
    if (std::fabs(p.x) == 1.f && std::fabs(p.y) == 1.f && std::fabs(p.z) == 1.f) break;
  }
  ASSERT_LT(corner, f.x.size());
  const FreeDirections none = free_directions(f.view(), faces.data(), corner, closed_fan(f.view(), corner));
  EXPECT_EQ(norm2(share_move(f, corner, none)), 0.f);
}

// The result moves continuously with the noise it is filtered for, also where a pass count
// changes (1 + 10σ normal passes: 3 at σ = 0.2).
TEST(KernelRefine, ResultIsContinuousInTheNoise) {
  Mesh m = test::make_icosphere(4);
  add_gaussian_noise(m, 0.2, 3);
  CpuEngine engine(2);
  auto run = [&](float noise) {
    Params p;
    p.filtering.refine.known_noise = noise;
    FrameResult out;
    EXPECT_TRUE(engine.process(m.view(), p, out).ok());
    return out.positions;
  };
  const std::vector<float> below = run(0.1999f), above = run(0.2001f), far = run(0.25f);
  const double edge = mean_edge_length(m.view());
  EXPECT_LT(test::max_displacement(below, above), 0.01 * edge);
  EXPECT_GT(test::max_displacement(below, far), 0.01 * edge);  // and the noise does matter
}

// More noise, more error, on the bundled CAD part: the result's error rises with the noise
// (no jump where a regime would switch) and stays far under the noisy input's, in face normals
// and in vertex positions.
TEST(KernelRefine, ErrorRisesWithTheNoiseAndStaysUnderTheInputs) {
  Mesh clean;
  const std::string path = std::string(FQ_SOURCE_DIR) + "/data/fandisk.ply";
  ASSERT_TRUE(io::read_mesh(path, clean).ok()) << path;
  CpuEngine engine(2);
  double last = 0.0;
  for (double s : {0.05, 0.1, 0.15, 0.2, 0.3, 0.5}) {
    Mesh noisy = clean;
    add_gaussian_noise(noisy, s, 5);
    FrameResult out;
    ASSERT_TRUE(engine.process(noisy.view(), Params{}, out).ok());
    const double in = mean_face_normal_error(clean.view(), noisy.positions.data()).mean_radians;
    const double e = mean_face_normal_error(clean.view(), out.positions.data()).mean_radians;
    SCOPED_TRACE(s);
    EXPECT_GT(e, last);
    EXPECT_LT(e, 0.5 * in);
    EXPECT_LT(rmse_over_diagonal(clean.view(), out.positions.data()),
              rmse_over_diagonal(clean.view(), noisy.positions.data()));
    last = e;
  }
}

// On a smooth surface with noise along the normal, the estimate finds the noise added (in the
// noisy frame's mean edges, which noise along the normal barely lengthens).
TEST(KernelRefine, EstimateFindsTheNoiseAdded) {
  const Mesh clean = test::make_icosphere(5);
  CpuEngine engine(2);
  for (double s : {0.02, 0.05, 0.1, 0.2, 0.3}) {
    Mesh noisy = clean;
    add_normal_noise(noisy, s, 11);
    FrameResult out;
    ASSERT_TRUE(engine.process(noisy.view(), Params{}, out).ok());
    SCOPED_TRACE(s);
    EXPECT_GT(out.noise_estimate, 0.85 * s);
    EXPECT_LT(out.noise_estimate, 1.15 * s);
    EXPECT_EQ(out.filter_noise, out.noise_estimate);
  }
}

// Noise along one direction (eval/noise.h's depth noise, along z, growing at grazing angles) on a
// sphere: the estimate reads it, and the filter then undoes the slides it made within the surface
// (a larger tangential share, and the slides along it kept) instead of cutting them back as it
// does for white noise of the same normal part (the noise given as known: white noise).
TEST(KernelRefine, NoiseAlongOneDirectionIsSlidBack) {
  const Mesh clean = test::make_icosphere(5);
  CpuEngine engine(2);
  for (double s : {0.1, 0.2}) {
    Mesh noisy = clean;
    add_depth_noise(noisy, s, 13);
    FrameResult directional, white;
    ASSERT_TRUE(engine.process(noisy.view(), Params{}, directional).ok());
    Params as_white;
    as_white.filtering.refine.known_noise = directional.filter_noise;
    ASSERT_TRUE(engine.process(noisy.view(), as_white, white).ok());
    SCOPED_TRACE(s);
    EXPECT_GT(directional.noise_directional, 0.5 * s);
    EXPECT_GT(std::fabs(directional.noise_direction.z), 0.9f);
    EXPECT_EQ(white.filter_noise, directional.filter_noise);
    EXPECT_LT(rmse_over_diagonal(clean.view(), directional.positions.data()),
              0.9 * rmse_over_diagonal(clean.view(), white.positions.data()));
    EXPECT_LT(mean_face_normal_error(clean.view(), directional.positions.data()).mean_radians,
              mean_face_normal_error(clean.view(), white.positions.data()).mean_radians);
  }
}

TEST(KernelRefine, RefinementBeatsThePapersFilterOnANoisyCube) {
  const Mesh clean = test::make_cube(12);
  Mesh noisy = clean;
  add_gaussian_noise(noisy, 0.3, 7);
  CpuEngine engine(2);
  Params qf;
  qf.filtering.method = FilterMethod::kQuadric;
  Params qf_plus;
  FrameResult a, b;
  ASSERT_TRUE(engine.process(noisy.view(), qf, a).ok());
  ASSERT_TRUE(engine.process(noisy.view(), qf_plus, b).ok());
  const double e_qf = mean_face_normal_error(clean.view(), a.positions.data()).mean_radians;
  const double e_plus = mean_face_normal_error(clean.view(), b.positions.data()).mean_radians;
  EXPECT_LT(e_plus, 0.7 * e_qf) << "qf " << e_qf << " qf+ " << e_plus;
}

TEST(KernelRefine, ThreadCountDoesNotChangeTheBits) {
  Mesh m = test::make_icosphere(4);
  add_gaussian_noise(m, 0.3, 3);
  Params p;
  FrameResult one, three;
  CpuEngine e1(1), e3(3);
  ASSERT_TRUE(e1.process(m.view(), p, one).ok());
  ASSERT_TRUE(e3.process(m.view(), p, three).ok());
  ASSERT_EQ(one.positions.size(), three.positions.size());
  EXPECT_EQ(std::memcmp(one.positions.data(), three.positions.data(), one.positions.size() * sizeof(float)),
            0);
}

}  // namespace
}  // namespace fq
