// A textured OBJ (per-corner `vt` and `vn`, quads, a material library with two materials)
// through read_mesh, moved as a filter moves it, and written as OBJ and glb: the outputs are
// parsed by assimp, not by fq's readers, and must keep every corner's texture coordinate and
// normal, each triangle's material and the library.
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <gtest/gtest.h>

#include <assimp/Importer.hpp>
#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>

#include "io/mesh_io.h"
#include "tests/io/io_test_util.h"

namespace fq::io {
namespace {

constexpr int kN = 6;  // grid of kN x kN vertices, (kN - 1)^2 quads

/// The grid: vertex (i, j) has texture coordinate (i, j) / (kN - 1) on every corner; corners
/// alternate between two normals; the first three rows of quads are red_paint, the rest
/// blue_paint (a material library beside it, the red one with a texture).
void write_textured_obj(const test::ScratchDir& dir) {
  std::ostringstream obj;
  obj << "mtllib paint.mtl\n";
  for (int i = 0; i < kN; ++i)
    for (int j = 0; j < kN; ++j) obj << "v " << i << " " << j << " " << 0.05 * std::sin(i + j) << "\n";
  for (int i = 0; i < kN; ++i)
    for (int j = 0; j < kN; ++j) obj << "vt " << i / double(kN - 1) << " " << j / double(kN - 1) << "\n";
  obj << "vn 0 0 1\nvn 0 0.6 0.8\n";
  for (int i = 0; i + 1 < kN; ++i) {
    obj << (i < 3 ? "usemtl red_paint\n" : "usemtl blue_paint\n");
    for (int j = 0; j + 1 < kN; ++j) {
      const int a = i * kN + j + 1, b = a + kN;
      obj << "f " << a << "/" << a << "/1 " << b << "/" << b << "/2 " << b + 1 << "/" << b + 1 << "/1 "
          << a + 1 << "/" << a + 1 << "/2\n";
    }
  }
  test::write_bytes(dir.file("grid.obj"), obj.str());
  test::write_bytes(dir.file("paint.mtl"),
                    "newmtl red_paint\nKd 0.8 0.1 0.1\nmap_Kd skin.png\nnewmtl blue_paint\nKd 0.1 0.1 0.8\n");
}

/// read_mesh, then every position moved (as a filter does), then write_mesh to `out`.
void move_and_write(const std::string& in, const std::string& out) {
  Mesh mesh;
  MeshAttributes attributes;
  ASSERT_TRUE(read_mesh(in, mesh, &attributes).ok());
  for (float& x : mesh.positions) x *= 1.5f;
  WriteOptions options;
  options.attributes = &attributes;
  std::vector<std::string> dropped;
  const Status s = write_mesh(out, mesh.view(), nullptr, 0, options, &dropped);
  ASSERT_TRUE(s.ok()) << s.message();
  EXPECT_TRUE(dropped.empty()) << dropped.front();
}

std::string material_name(const aiScene& scene, const aiMesh& m) {
  aiString name;
  scene.mMaterials[m.mMaterialIndex]->Get(AI_MATKEY_NAME, name);
  return name.C_Str();
}

std::string diffuse_texture(const aiScene& scene, const std::string& material) {
  for (unsigned i = 0; i < scene.mNumMaterials; ++i) {
    aiString name, path;
    scene.mMaterials[i]->Get(AI_MATKEY_NAME, name);
    if (material == name.C_Str() &&
        scene.mMaterials[i]->GetTexture(aiTextureType_DIFFUSE, 0, &path) == AI_SUCCESS)
      return path.C_Str();
  }
  return "";
}

/// Checks every corner of every triangle assimp reads from `path`.
void expect_corners_and_materials(const std::string& path) {
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(path, 0);
  ASSERT_NE(scene, nullptr) << importer.GetErrorString();
  std::map<std::string, int> triangles_of;
  int normals_up = 0, normals_tilted = 0;
  for (unsigned i = 0; i < scene->mNumMeshes; ++i) {
    const aiMesh& m = *scene->mMeshes[i];
    ASSERT_TRUE(m.HasTextureCoords(0) && m.HasNormals()) << path;
    for (unsigned f = 0; f < m.mNumFaces; ++f) {
      ASSERT_EQ(m.mFaces[f].mNumIndices, 3u);
      const std::string material = material_name(*scene, m);
      ++triangles_of[material];
      for (unsigned k = 0; k < 3; ++k) {
        const unsigned v = m.mFaces[f].mIndices[k];
        const aiVector3D p = m.mVertices[v] / 1.5f, uv = m.mTextureCoords[0][v], n = m.mNormals[v];
        // Quads of rows i < 3 (corners at x <= 3 before the move) are red_paint, the others blue.
        EXPECT_TRUE(material == "red_paint" ? p.x < 3.001f : p.x > 2.999f) << material << " at x " << p.x;
        EXPECT_NEAR(uv.x, p.x / (kN - 1), 1e-5) << path;  // the corner's vt, though the position moved
        EXPECT_NEAR(uv.y, p.y / (kN - 1), 1e-5) << path;
        (std::abs(n.z - 1) < 1e-5 ? normals_up : normals_tilted) += 1;
        EXPECT_TRUE(std::abs(n.z - 1) < 1e-5 || (std::abs(n.y - 0.6) < 1e-5 && std::abs(n.z - 0.8) < 1e-5));
      }
    }
  }
  EXPECT_EQ(triangles_of["red_paint"], 2 * 3 * (kN - 1)) << path;  // quads split in two
  EXPECT_EQ(triangles_of["blue_paint"], 2 * 2 * (kN - 1)) << path;
  EXPECT_GT(normals_up, 0);
  EXPECT_GT(normals_tilted, 0);
}

TEST(ObjCorners, ObjRoundTripKeepsCornersMaterialsAndLibrary) {
  test::ScratchDir dir;
  write_textured_obj(dir);
  std::filesystem::create_directory(dir.file("out"));
  move_and_write(dir.file("grid.obj"), dir.file("out/smooth.obj"));
  EXPECT_NE(test::read_bytes(dir.file("out/smooth.obj")).find("mtllib ../paint.mtl\n"), std::string::npos);
  expect_corners_and_materials(dir.file("out/smooth.obj"));
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(dir.file("out/smooth.obj"), 0);
  ASSERT_NE(scene, nullptr);
  EXPECT_EQ(diffuse_texture(*scene, "red_paint"), "skin.png");  // read from the kept library
}

TEST(ObjCorners, GlbKeepsCornersAndMaterialsWithTheirTexture) {
  test::ScratchDir dir;
  write_textured_obj(dir);
  std::filesystem::create_directory(dir.file("out"));
  move_and_write(dir.file("grid.obj"), dir.file("out/smooth.glb"));
  expect_corners_and_materials(dir.file("out/smooth.glb"));
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(dir.file("out/smooth.glb"), 0);
  ASSERT_NE(scene, nullptr);
  EXPECT_EQ(diffuse_texture(*scene, "red_paint"), "../skin.png");  // from the glb's folder
  EXPECT_EQ(diffuse_texture(*scene, "blue_paint"), "");
}

TEST(ObjCorners, PlyKeepsCornerUvsAsTexcoordAndNamesTheRest) {
  test::ScratchDir dir;
  write_textured_obj(dir);
  Mesh mesh;
  MeshAttributes attributes;
  ASSERT_TRUE(read_mesh(dir.file("grid.obj"), mesh, &attributes).ok());
  WriteOptions options;
  options.attributes = &attributes;
  std::vector<std::string> dropped;
  ASSERT_TRUE(write_mesh(dir.file("out.ply"), mesh.view(), nullptr, 0, options, &dropped).ok());
  ASSERT_EQ(dropped.size(), 2u);  // one line per group: the corner normals, the materials
  EXPECT_NE(dropped[0].find("per-corner normals"), std::string::npos) << dropped[0];
  EXPECT_NE(dropped[1].find("paint.mtl"), std::string::npos) << dropped[1];
  Mesh back;
  MeshAttributes kept;
  ASSERT_TRUE(read_mesh(dir.file("out.ply"), back, &kept).ok());
  ASSERT_EQ(kept.face.size(), 1u);
  EXPECT_EQ(kept.face[0].name, "texcoord");
  ASSERT_EQ(kept.face[0].values.size(), 6 * back.num_triangles());
  for (size_t c = 0; c < 3 * size_t(back.num_triangles()); ++c) {
    const float* p = &back.positions[3 * size_t(back.triangles[c])];
    EXPECT_NEAR(kept.face[0].values[2 * c], p[0] / (kN - 1), 1e-6);
    EXPECT_NEAR(kept.face[0].values[2 * c + 1], p[1] / (kN - 1), 1e-6);
  }
}

}  // namespace
}  // namespace fq::io
