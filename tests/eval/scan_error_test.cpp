// scan_error and faces_over_reference against errors known by construction: a plane as the
// reference, scans of it lifted, tilted, wound the other way round and hanging over its edge.
#include "eval/scan_error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "kernels/frame_prep.h"
#include "tests/support/test_meshes.h"

namespace fq {
namespace {

using test::make_plane_grid;

// The reference: the plane z = 0 over [0, 20]², edge 1. A scan: a 10 × 10 grid of spacing 0.5
// placed at (x0, y0), every vertex lifted by lift(x, y).
template <typename Lift>
Mesh scan_at(float x0, float y0, Lift lift) {
  Mesh s = make_plane_grid(10, 10, 0.5f);
  for (uint32_t v = 0; v < s.num_vertices(); ++v) {
    float* p = &s.positions[3 * size_t(v)];
    p[0] += x0;
    p[1] += y0;
    p[2] = lift(p[0], p[1]);
  }
  return s;
}

double count(const std::vector<uint8_t>& over) {
  double n = 0;
  for (uint8_t o : over) n += o;
  return n;
}

TEST(ScanError, LiftedScanIsAtItsHeightWithNoNormalError) {
  const Mesh ref = make_plane_grid(20, 20);
  const Mesh scan = scan_at(5.f, 5.f, [](float, float) { return 0.1f; });
  const std::vector<uint8_t> over = faces_over_reference(ref.view(), scan.view());
  EXPECT_EQ(count(over), scan.num_triangles());
  const double edge = mean_edge_length(scan.view());
  const ScanError e = scan_error(ref.view(), scan.view(), nullptr, over.data(), edge);
  EXPECT_EQ(e.faces_used, scan.num_triangles());
  EXPECT_NEAR(e.normal_error, 0.0, 1e-6);
  EXPECT_NEAR(e.distance, 0.1 / edge, 1e-6);
  EXPECT_FALSE(e.flipped);
  EXPECT_NEAR(e.normal_error_coarse, 0.0, 1e-6);
  EXPECT_GT(e.reference_faces_used, 0u);
}

TEST(ScanError, AtTheReferencesScaleDetailFinerThanItsTrianglesAveragesOut) {
  // A reference of edge 4 and a scan of step 0.5 zigzagging in x with period 1 (two steps,
  // heights ±0.035): every scan face is tilted by about 0.14 rad, but over a reference
  // triangle the tilts cancel.
  const Mesh ref = make_plane_grid(5, 5, 4.f);
  const Mesh scan = scan_at(
      5.f, 5.f, [](float x, float) { return 0.05f * std::sin(2.f * float(M_PI) * x + float(M_PI) / 4.f); });
  const ScanError e = scan_error(ref.view(), scan.view(), nullptr, nullptr, 1.0);
  EXPECT_GT(e.normal_error, 0.1);
  EXPECT_LT(e.normal_error_coarse, 0.25 * e.normal_error);
  // A tilt is not detail: both measures see all of it.
  const double slope = 0.2;
  const Mesh tilted = scan_at(5.f, 5.f, [&](float x, float) { return float(slope * (x - 7.5)); });
  const ScanError t = scan_error(ref.view(), tilted.view(), nullptr, nullptr, 1.0);
  EXPECT_NEAR(t.normal_error_coarse, std::atan(slope), 1e-6);
}

TEST(ScanError, TiltedScanMeasuresTheTiltAndAReversedWindingTheSame) {
  const Mesh ref = make_plane_grid(20, 20);
  const double slope = 0.2;
  Mesh scan = scan_at(5.f, 5.f, [&](float x, float) { return float(slope * (x - 7.5)); });
  const ScanError e = scan_error(ref.view(), scan.view(), nullptr, nullptr, 1.0);
  EXPECT_NEAR(e.normal_error, std::atan(slope), 1e-6);
  // Centroids at heights slope·(x − 7.5) over x in [5, 10]: RMS well above 0 and below the ends' 0.5.
  EXPECT_GT(e.distance, 0.1);
  EXPECT_LT(e.distance, 0.5);
  for (uint32_t t = 0; t < scan.num_triangles(); ++t)
    std::swap(scan.triangles[3 * t + 1], scan.triangles[3 * t + 2]);
  const ScanError f = scan_error(ref.view(), scan.view(), nullptr, nullptr, 1.0);
  EXPECT_TRUE(f.flipped);
  EXPECT_NEAR(f.normal_error, e.normal_error, 1e-9);
  EXPECT_NEAR(f.normal_error_coarse, e.normal_error_coarse, 1e-9);
  EXPECT_NEAR(f.distance, e.distance, 1e-12);
}

TEST(ScanError, OnlyFacesOverTheReferenceCount) {
  const Mesh ref = make_plane_grid(20, 20);
  // Half the scan hangs past the reference's edge at x = 20: those faces' closest points are
  // on the boundary triangles and must not count; the inner half counts.
  const Mesh scan = scan_at(17.5f, 5.f, [](float, float) { return 0.f; });
  const std::vector<uint8_t> over = faces_over_reference(ref.view(), scan.view());
  for (uint32_t t = 0; t < scan.num_triangles(); ++t) {
    const uint32_t* tri = &scan.triangles[3 * size_t(t)];
    double cx = 0;
    for (int k = 0; k < 3; ++k) cx += scan.positions[3 * size_t(tri[k])] / 3.0;
    if (cx > 19.f) {
      EXPECT_EQ(over[t], 0) << "face at x " << cx;  // over or next to a boundary triangle
    }
    if (cx < 18.9f) {
      EXPECT_EQ(over[t], 1) << "face at x " << cx;
    }
  }
  // A scan floating 5 mean edges (its own: 0.5 · (2 + √2) / 3) above the plane is over nothing.
  const Mesh far = scan_at(5.f, 5.f, [](float, float) { return 3.f; });
  EXPECT_EQ(count(faces_over_reference(ref.view(), far.view())), 0);
  // The measure then counts no face, and says so with NaN.
  const std::vector<uint8_t> none(far.num_triangles(), 0);
  const ScanError e = scan_error(ref.view(), far.view(), nullptr, none.data(), 1.0);
  EXPECT_EQ(e.faces_used, 0u);
  EXPECT_TRUE(std::isnan(e.normal_error));
}

TEST(ScanError, MovedPositionsAreMeasuredOnTheFacesOfTheRawScan) {
  const Mesh ref = make_plane_grid(20, 20);
  const Mesh scan =
      scan_at(5.f, 5.f, [](float x, float y) { return 0.05f * std::sin(3.f * x) * std::cos(2.f * y); });
  const std::vector<uint8_t> over = faces_over_reference(ref.view(), scan.view());
  const ScanError raw = scan_error(ref.view(), scan.view(), nullptr, over.data(), 1.0);
  std::vector<float> flat = scan.positions;
  for (uint32_t v = 0; v < scan.num_vertices(); ++v) flat[3 * size_t(v) + 2] = 0.f;
  const ScanError smoothed = scan_error(ref.view(), scan.view(), flat.data(), over.data(), 1.0);
  EXPECT_GT(raw.normal_error, 0.01);
  EXPECT_NEAR(smoothed.normal_error, 0.0, 1e-6);
  EXPECT_NEAR(smoothed.distance, 0.0, 1e-7);
  EXPECT_EQ(smoothed.faces_used, raw.faces_used);
}

}  // namespace
}  // namespace fq
