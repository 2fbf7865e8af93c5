// fqfilter's normals follow the filtered surface: an OBJ's per-corner normals (`vn`) are
// recomputed within the input's normal groups, so a hard edge stays hard; --keep-normals
// writes them unchanged; a glb always has normals. Outputs are parsed by assimp, and the
// expected normals are computed here from the positions assimp reads.
#include <assimp/scene.h>
#include <gtest/gtest.h>

#include <array>
#include <assimp/Importer.hpp>
#include <cmath>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "tests/io/fqfilter_run.h"
#include "tests/io/io_test_util.h"

namespace {

using fq::test::run_fqfilter;
using fq::test::ScratchDir;

constexpr int kN = 9;      // grid of kN x kN vertices
constexpr int kRidge = 4;  // the column of the hard edge
constexpr double kDegree = std::numbers::pi / 180;
const aiVector3D kLeft(-0.6f, 0.f, 0.8f), kRight(0.6f, 0.f, 0.8f);  // the input's two normals

/// A noisy roof: two slopes meeting at x = kRidge, each side's corners with its own `vn`
/// (a CAD or photogrammetry export of a hard edge); `with_normals` false: no `vn` at all.
std::string roof_obj(bool with_normals) {
  std::ostringstream s;
  for (int i = 0; i < kN; ++i) {
    for (int j = 0; j < kN; ++j) {
      const double noise = 0.04 * std::sin(12.9898 * i + 78.233 * j);
      s << "v " << i << " " << j << " " << 0.75 * (kRidge - std::abs(i - kRidge)) + noise << "\n";
    }
  }
  if (with_normals)
    s << "vn " << kLeft.x << " 0 " << kLeft.z << "\nvn " << kRight.x << " 0 " << kRight.z << "\n";
  for (int i = 0; i + 1 < kN; ++i) {
    for (int j = 0; j + 1 < kN; ++j) {
      const int a = i * kN + j + 1, b = a + kN, n = i < kRidge ? 1 : 2;  // OBJ counts from 1
      const std::array<int, 3> halves[2] = {{a, b, b + 1}, {a, b + 1, a + 1}};
      for (const std::array<int, 3>& t : halves) {
        s << "f";
        for (int k = 0; k < 3; ++k) s << " " << t[k] << (with_normals ? "//" + std::to_string(n) : "");
        s << "\n";
      }
    }
  }
  return s.str();
}

/// One triangle corner as a reader gives it.
struct Corner {
  aiVector3D position, normal;
};
using Triangle = std::array<Corner, 3>;

/// Every triangle of every mesh assimp reads from `path` (no post-processing: nothing
/// recomputed or joined by assimp).
std::vector<Triangle> read_triangles(const std::string& path) {
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(path, 0);
  EXPECT_NE(scene, nullptr) << importer.GetErrorString();
  std::vector<Triangle> out;
  for (unsigned i = 0; scene && i < scene->mNumMeshes; ++i) {
    const aiMesh& m = *scene->mMeshes[i];
    EXPECT_TRUE(m.HasNormals()) << path;
    for (unsigned f = 0; m.HasNormals() && f < m.mNumFaces; ++f) {
      Triangle t;
      for (unsigned k = 0; k < 3; ++k)
        t[k] = {m.mVertices[m.mFaces[f].mIndices[k]], m.mNormals[m.mFaces[f].mIndices[k]]};
      out.push_back(t);
    }
  }
  return out;
}

bool is_left(const Triangle& t) { return (t[0].position.x + t[1].position.x + t[2].position.x) / 3 < kRidge; }

/// A vertex by its position (written and read exactly), and with `by_side` its side of the ridge.
using GroupKey = std::tuple<float, float, float, bool>;
GroupKey group_of(const Triangle& t, int k, bool by_side) {
  const aiVector3D& p = t[k].position;
  return {p.x, p.y, p.z, by_side && is_left(t)};
}

/// Checks every corner's normal against the area-weighted normal of its group's triangles,
/// computed from the positions read back: per vertex, or per vertex and side of the ridge.
/// Returns the normals of the groups.
std::map<GroupKey, aiVector3D> expect_area_weighted(const std::vector<Triangle>& triangles, bool by_side) {
  std::map<GroupKey, aiVector3D> sum;
  for (const Triangle& t : triangles) {
    const aiVector3D area_normal = (t[1].position - t[0].position) ^ (t[2].position - t[0].position);
    for (int k = 0; k < 3; ++k) sum[group_of(t, k, by_side)] += area_normal;
  }
  for (auto& [key, n] : sum) n.Normalize();
  for (const Triangle& t : triangles) {
    for (int k = 0; k < 3; ++k) {
      const aiVector3D& expected = sum[group_of(t, k, by_side)];
      EXPECT_NEAR(t[k].normal.Length(), 1.f, 1e-5f);
      EXPECT_GT(t[k].normal * expected, std::cos(0.1 * kDegree)) << "a corner at x " << t[k].position.x;
    }
  }
  return sum;
}

/// The roof (with or without its normals) through fqfilter to `out` (two threads, quiet, plus
/// `extra`), read back by assimp; empty, with the test failed, when something went wrong.
std::vector<Triangle> filtered_roof(const ScratchDir& dir, bool with_normals, const std::string& out,
                                    const std::string& extra = "") {
  fq::test::write_bytes(dir.file("roof.obj"), roof_obj(with_normals));
  std::vector<std::string> args{dir.file("roof.obj"), dir.file(out), "--threads", "2", "--quiet"};
  if (!extra.empty()) args.push_back(extra);
  const fq::test::RunResult r = run_fqfilter(args, dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  std::vector<Triangle> triangles =
      r.exit_code == 0 ? read_triangles(dir.file(out)) : std::vector<Triangle>{};
  EXPECT_EQ(triangles.size(), 2u * (kN - 1) * (kN - 1)) << out;
  return triangles;
}

TEST(FqfilterNormals, ObjCornerNormalsFollowTheFilteredFacesWithinTheirGroups) {
  ScratchDir dir;
  const auto groups = expect_area_weighted(filtered_roof(dir, true, "smooth.obj"), true);
  int ridge = 0, moved = 0;
  for (const auto& [key, n] : groups) {
    const auto [x, y, z, left_side] = key;
    if (!left_side && groups.count({x, y, z, true})) {
      // A ridge vertex: two groups, whose normals stay apart (the input's are 74 degrees apart).
      EXPECT_LT(groups.at({x, y, z, true}) * n, std::cos(30 * kDegree)) << "ridge vertex at y " << y;
      ++ridge;
    }
    moved += n * (left_side ? kLeft : kRight) < std::cos(0.5 * kDegree);
  }
  EXPECT_EQ(ridge, kN);
  EXPECT_GT(moved, 0);  // not the input's normals (the noise tilts some by 1.6 degrees)
}

TEST(FqfilterNormals, KeepNormalsWritesTheInputsUnchanged) {
  ScratchDir dir;
  for (const Triangle& t : filtered_roof(dir, true, "kept.obj", "--keep-normals")) {
    for (const Corner& c : t)
      EXPECT_EQ(c.normal, is_left(t) ? kLeft : kRight) << "a corner at x " << c.position.x;
  }
  EXPECT_NE(fq::test::read_bytes(dir.file("kept.obj")).find("vn -0.6 0 0.8\nvn 0.6 0 0.8\n"),
            std::string::npos);
}

TEST(FqfilterNormals, GlbHasTheRecomputedCornerNormals) {
  ScratchDir dir;
  expect_area_weighted(filtered_roof(dir, true, "smooth.glb"), true);
}

TEST(FqfilterNormals, GlbOfAnInputWithoutNormalsGetsVertexNormals) {
  ScratchDir dir;
  expect_area_weighted(filtered_roof(dir, false, "smooth.glb"), false);
  // --keep-normals has none to keep: the glb still gets the surface's.
  expect_area_weighted(filtered_roof(dir, false, "kept.glb", "--keep-normals"), false);
}

}  // namespace
