#include "io/assimp_io.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <array>
#include <assimp/Exporter.hpp>
#include <assimp/Importer.hpp>
#include <cstring>
#include <map>
#include <memory>

#include "io/cluster_colors.h"
#include "io/mesh_io.h"

namespace fq::io {

namespace {

using Position = std::array<float, 3>;

/// Welds the triangle corners of `m` (assimp gives three unshared vertices per STL facet).
void weld(const aiMesh& m, Mesh& out) {
  std::map<Position, uint32_t> index;
  for (unsigned f = 0; f < m.mNumFaces; ++f) {
    for (unsigned k = 0; k < 3; ++k) {
      const aiVector3D& p = m.mVertices[m.mFaces[f].mIndices[k]];
      const auto [it, added] = index.try_emplace(Position{p.x, p.y, p.z}, out.num_vertices());
      if (added) out.positions.insert(out.positions.end(), {p.x, p.y, p.z});
      out.triangles.push_back(it->second);
    }
  }
}

/// The first pair of vertex properties that are texture coordinates, or nulls.
std::array<const ElementProperty*, 2> texture_coordinates(const MeshAttributes& a) {
  for (auto [u, v] :
       {std::pair{"u", "v"}, {"s", "t"}, {"texture_u", "texture_v"}, {"texture_s", "texture_t"}}) {
    if (a.find_vertex(u) && a.find_vertex(v)) return {a.find_vertex(u), a.find_vertex(v)};
  }
  return {nullptr, nullptr};
}

double unit_channel(const ElementProperty& p, size_t v) {
  const bool is_float = p.type == ScalarType::kFloat32 || p.type == ScalarType::kFloat64;
  return is_float ? p.values[v] : p.values[v] / 255.0;
}

/// Vertex colours from the input (or the clusters); which properties it used go to `used`.
bool fill_colours(aiMesh& m, const uint32_t* labels, const MeshAttributes& a, bool colour_clusters,
                  std::vector<std::string>& used) {
  const ElementProperty *r = a.find_vertex("red"), *g = a.find_vertex("green"), *b = a.find_vertex("blue");
  const ElementProperty* alpha = a.find_vertex("alpha");
  const bool clusters = labels && (colour_clusters || !(r && g && b));
  if (!clusters && !(r && g && b)) return false;
  m.mColors[0] = new aiColor4D[m.mNumVertices];
  for (size_t v = 0; v < m.mNumVertices; ++v) {
    if (clusters) {
      const Rgb8 c = cluster_color(labels[v]);
      m.mColors[0][v] = aiColor4D(c.r / 255.f, c.g / 255.f, c.b / 255.f, 1.f);
    } else {
      m.mColors[0][v] = aiColor4D(float(unit_channel(*r, v)), float(unit_channel(*g, v)),
                                  float(unit_channel(*b, v)), alpha ? float(unit_channel(*alpha, v)) : 1.f);
    }
  }
  if (r && g && b && !clusters) used.insert(used.end(), {"red", "green", "blue", "alpha"});
  return true;
}

std::unique_ptr<aiScene> make_scene(const MeshView& mesh) {
  auto scene = std::make_unique<aiScene>();
  scene->mRootNode = new aiNode("fq");
  scene->mRootNode->mNumMeshes = 1;
  scene->mRootNode->mMeshes = new unsigned[1]{0};
  scene->mNumMaterials = 1;
  scene->mMaterials = new aiMaterial* [1] { new aiMaterial() };
  scene->mNumMeshes = 1;
  auto* m = new aiMesh();
  scene->mMeshes = new aiMesh* [1] { m };
  m->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
  m->mNumVertices = mesh.num_vertices;
  m->mVertices = new aiVector3D[mesh.num_vertices];
  for (uint32_t v = 0; v < mesh.num_vertices; ++v) {
    const float* p = mesh.positions + 3 * size_t(v);
    m->mVertices[v] = aiVector3D(p[0], p[1], p[2]);
  }
  m->mNumFaces = mesh.num_triangles;
  m->mFaces = new aiFace[mesh.num_triangles];
  for (uint32_t t = 0; t < mesh.num_triangles; ++t) {
    m->mFaces[t].mNumIndices = 3;
    m->mFaces[t].mIndices = new unsigned[3];
    for (int k = 0; k < 3; ++k) m->mFaces[t].mIndices[k] = mesh.triangles[3 * size_t(t) + k];
  }
  return scene;
}

/// Normals and texture coordinates of `a` onto `m`; the property names used go to `used`.
void fill_normals_and_uvs(aiMesh& m, const MeshAttributes& a, std::vector<std::string>& used) {
  const ElementProperty *nx = a.find_vertex("nx"), *ny = a.find_vertex("ny"), *nz = a.find_vertex("nz");
  if (nx && ny && nz) {
    m.mNormals = new aiVector3D[m.mNumVertices];
    for (size_t v = 0; v < m.mNumVertices; ++v)
      m.mNormals[v] = aiVector3D(float(nx->values[v]), float(ny->values[v]), float(nz->values[v]));
    used.insert(used.end(), {"nx", "ny", "nz"});
  }
  const auto uv = texture_coordinates(a);
  if (uv[0]) {
    m.mNumUVComponents[0] = 2;
    m.mTextureCoords[0] = new aiVector3D[m.mNumVertices];
    for (size_t v = 0; v < m.mNumVertices; ++v)
      m.mTextureCoords[0][v] = aiVector3D(float(uv[0]->values[v]), float(uv[1]->values[v]), 0.f);
    used.insert(used.end(), {uv[0]->name, uv[1]->name});
  }
}

}  // namespace

Status read_ascii_stl(const std::string& path, Mesh& out) {
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(path, aiProcess_Triangulate);
  if (!scene || scene->mNumMeshes == 0)
    return invalid_input("cannot decode '" + path + "': " + importer.GetErrorString());
  for (unsigned i = 0; i < scene->mNumMeshes; ++i) {
    if (scene->mMeshes[i]->mPrimitiveTypes & ~aiPrimitiveType_TRIANGLE)
      return invalid_input("'" + path + "' is not a triangle mesh");
    weld(*scene->mMeshes[i], out);
  }
  return {};
}

Status write_with_assimp(const std::string& path, const MeshView& mesh, const uint32_t* labels,
                         const MeshAttributes* attributes, bool colour_clusters,
                         std::vector<std::string>& dropped) {
  const bool glb = lower_extension(path) == ".glb";
  const std::unique_ptr<aiScene> scene = make_scene(mesh);
  const MeshAttributes none;
  const MeshAttributes& a = attributes ? *attributes : none;
  std::vector<std::string> used;
  fill_normals_and_uvs(*scene->mMeshes[0], a, used);
  const bool coloured = glb && fill_colours(*scene->mMeshes[0], labels, a, colour_clusters, used);
  for (const ElementProperty& p : a.vertex) {
    if (std::find(used.begin(), used.end(), p.name) == used.end())
      dropped.push_back("vertex property '" + p.name + "'");
  }
  for (const ElementProperty& p : a.face) dropped.push_back("face property '" + p.name + "'");
  if (labels)
    dropped.push_back(
        glb ? (coloured && (colour_clusters || !a.find_vertex("red"))
                   ? "cluster labels as integers (the vertex colours show the clusters)"
                   : "cluster labels (glb has no per-vertex integer property; try --colour-clusters)")
            : "cluster labels (OBJ has no per-vertex property for them)");
  Assimp::Exporter exporter;
  if (exporter.Export(scene.get(), glb ? "glb2" : "objnomtl", path) != aiReturn_SUCCESS)
    return invalid_argument("cannot write '" + path + "': " + exporter.GetErrorString());
  return {};
}

}  // namespace fq::io
