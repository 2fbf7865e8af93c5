#include "io/glb_writer.h"

#include <assimp/scene.h>

#include <algorithm>
#include <array>
#include <assimp/Exporter.hpp>
#include <filesystem>
#include <map>
#include <unordered_map>

#include "io/cluster_colors.h"
#include "io/mtl_library.h"
#include "io/surface_normals.h"

namespace fq::io {

namespace {

/// One glb primitive: a material's triangles over vertices of their own, one per distinct
/// (fq vertex, texture coordinate, normal) of its corners, since glTF's attributes are per
/// vertex (a texture seam splits a vertex in two).
struct Primitive {
  uint32_t material = 0;
  std::vector<uint32_t> vertex, uv, normal;  ///< per glb vertex: its sources (uv, normal: corner values)
  std::vector<uint32_t> triangles;
};

struct CornerKeyHash {
  size_t operator()(const std::array<uint32_t, 3>& k) const {
    return std::hash<uint64_t>()((uint64_t(k[0]) << 32) ^ (uint64_t(k[1]) * 0x9E3779B97F4A7C15ull) ^ k[2]);
  }
};

std::vector<Primitive> primitives(const MeshView& mesh, const MeshAttributes& a) {
  const bool corners = !a.corner_uv.empty() || !a.corner_normal.empty();
  const size_t groups = a.materials.empty() ? 1 : a.materials.names.size();
  std::vector<Primitive> out(groups);
  for (size_t g = 0; g < groups; ++g) out[g].material = uint32_t(g);
  if (!corners && groups == 1) {  // every vertex as it is, unused ones too
    out[0].vertex.resize(mesh.num_vertices);
    for (uint32_t v = 0; v < mesh.num_vertices; ++v) out[0].vertex[v] = v;
    out[0].triangles.assign(mesh.triangles, mesh.triangles + 3 * size_t(mesh.num_triangles));
    return out;
  }
  std::vector<std::unordered_map<std::array<uint32_t, 3>, uint32_t, CornerKeyHash>> index(groups);
  for (size_t c = 0; c < 3 * size_t(mesh.num_triangles); ++c) {
    const size_t g = a.materials.empty() ? 0 : a.materials.of_triangle[c / 3];
    const std::array<uint32_t, 3> key{mesh.triangles[c], a.corner_uv.empty() ? 0 : a.corner_uv.corners[c],
                                      a.corner_normal.empty() ? 0 : a.corner_normal.corners[c]};
    Primitive& p = out[g];
    const auto [it, added] = index[g].try_emplace(key, uint32_t(p.vertex.size()));
    if (added) {
      p.vertex.push_back(key[0]);
      p.uv.push_back(key[1]);
      p.normal.push_back(key[2]);
    }
    p.triangles.push_back(it->second);
  }
  std::erase_if(out, [](const Primitive& p) { return p.triangles.empty(); });
  return out;
}

double unit_channel(const ElementProperty& p, size_t v) {
  const bool is_float = p.type == ScalarType::kFloat32 || p.type == ScalarType::kFloat64;
  return is_float ? p.values[v] : p.values[v] / 255.0;
}

/// Vertex colours from the input (or the clusters); whether it wrote any.
bool fill_colours(aiMesh& m, const Primitive& p, const uint32_t* labels, const MeshAttributes& a,
                  bool colour_clusters) {
  const ElementProperty *r = a.find_vertex("red"), *g = a.find_vertex("green"), *b = a.find_vertex("blue");
  const ElementProperty* alpha = a.find_vertex("alpha");
  const bool clusters = labels && (colour_clusters || !(r && g && b));
  if (!clusters && !(r && g && b)) return false;
  m.mColors[0] = new aiColor4D[m.mNumVertices];
  for (size_t i = 0; i < m.mNumVertices; ++i) {
    const uint32_t v = p.vertex[i];
    if (clusters) {
      const Rgb8 c = cluster_color(labels[v]);
      m.mColors[0][i] = aiColor4D(c.r / 255.f, c.g / 255.f, c.b / 255.f, 1.f);
    } else {
      m.mColors[0][i] = aiColor4D(float(unit_channel(*r, v)), float(unit_channel(*g, v)),
                                  float(unit_channel(*b, v)), alpha ? float(unit_channel(*alpha, v)) : 1.f);
    }
  }
  return true;
}

/// Normals and texture coordinates: the corner values when the input has them, else the
/// per-vertex properties, else (normals) `computed`. Which vertex properties it used go to `used`.
void fill_normals_and_uvs(aiMesh& m, const Primitive& p, const MeshAttributes& a,
                          const std::vector<std::array<float, 3>>& computed, std::vector<std::string>& used) {
  const ElementProperty *nx = a.find_vertex("nx"), *ny = a.find_vertex("ny"), *nz = a.find_vertex("nz");
  const auto uv = a.vertex_uv();
  m.mNormals = new aiVector3D[m.mNumVertices];
  if (!a.corner_uv.empty() || uv[0]) {
    m.mNumUVComponents[0] = 2;
    m.mTextureCoords[0] = new aiVector3D[m.mNumVertices];
  }
  for (size_t i = 0; i < m.mNumVertices; ++i) {
    const uint32_t v = p.vertex[i];
    if (!a.corner_normal.empty()) {
      const float* n = &a.corner_normal.values[3 * size_t(p.normal[i])];
      m.mNormals[i] = aiVector3D(n[0], n[1], n[2]);
    } else if (nx && ny && nz) {
      m.mNormals[i] = aiVector3D(float(nx->values[v]), float(ny->values[v]), float(nz->values[v]));
    } else {
      m.mNormals[i] = aiVector3D(computed[v][0], computed[v][1], computed[v][2]);
    }
    if (!a.corner_uv.empty()) {
      const float* t = &a.corner_uv.values[2 * size_t(p.uv[i])];
      m.mTextureCoords[0][i] = aiVector3D(t[0], t[1], 0.f);
    } else if (m.mTextureCoords[0]) {
      m.mTextureCoords[0][i] = aiVector3D(float(uv[0]->values[v]), float(uv[1]->values[v]), 0.f);
    }
  }
  if (a.corner_normal.empty() && nx && ny && nz) used.insert(used.end(), {"nx", "ny", "nz"});
  if (a.corner_uv.empty() && uv[0]) used.insert(used.end(), {uv[0]->name, uv[1]->name});
}

aiMesh* make_mesh(const MeshView& mesh, const Primitive& p) {
  auto* m = new aiMesh();
  m->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
  m->mMaterialIndex = p.material;
  m->mNumVertices = uint32_t(p.vertex.size());
  m->mVertices = new aiVector3D[m->mNumVertices];
  for (size_t i = 0; i < p.vertex.size(); ++i) {
    const float* x = mesh.positions + 3 * size_t(p.vertex[i]);
    m->mVertices[i] = aiVector3D(x[0], x[1], x[2]);
  }
  m->mNumFaces = uint32_t(p.triangles.size() / 3);
  m->mFaces = new aiFace[m->mNumFaces];
  for (uint32_t t = 0; t < m->mNumFaces; ++t) {
    m->mFaces[t].mNumIndices = 3;
    m->mFaces[t].mIndices = new unsigned[3];
    for (int k = 0; k < 3; ++k) m->mFaces[t].mIndices[k] = p.triangles[3 * size_t(t) + k];
  }
  return m;
}

/// The input's materials (name, diffuse colour, diffuse texture by its path from the
/// output's folder), or one default material.
void add_materials(aiScene& scene, const Materials& materials, const std::string& output) {
  const std::map<std::string, MtlMaterial> library =
      materials.library.empty() ? std::map<std::string, MtlMaterial>{} : read_mtl(materials.library);
  scene.mNumMaterials = unsigned(std::max<size_t>(1, materials.names.size()));
  scene.mMaterials = new aiMaterial*[scene.mNumMaterials];
  const auto folder = std::filesystem::absolute(output).parent_path();
  for (unsigned i = 0; i < scene.mNumMaterials; ++i) {
    auto* m = new aiMaterial();
    scene.mMaterials[i] = m;
    if (materials.names.empty()) continue;
    const aiString name(materials.names[i]);
    m->AddProperty(&name, AI_MATKEY_NAME);
    const auto found = library.find(materials.names[i]);
    if (found == library.end()) continue;
    if (found->second.has_diffuse) {
      const aiColor4D kd(found->second.diffuse[0], found->second.diffuse[1], found->second.diffuse[2], 1.f);
      m->AddProperty(&kd, 1, AI_MATKEY_COLOR_DIFFUSE);
      m->AddProperty(&kd, 1, AI_MATKEY_BASE_COLOR);
    }
    if (!found->second.texture.empty()) {
      const aiString texture(
          std::filesystem::path(found->second.texture).lexically_proximate(folder).generic_string());
      m->AddProperty(&texture, AI_MATKEY_TEXTURE_DIFFUSE(0));
      m->AddProperty(&texture, AI_MATKEY_TEXTURE(aiTextureType_BASE_COLOR, 0));
    }
  }
}

}  // namespace

Status write_glb(const std::string& path, const MeshView& mesh, const uint32_t* labels,
                 const MeshAttributes* attributes, bool colour_clusters, std::vector<std::string>& dropped) {
  const MeshAttributes none;
  const MeshAttributes& a = attributes ? *attributes : none;
  const std::vector<Primitive> parts = primitives(mesh, a);
  aiScene scene;
  scene.mRootNode = new aiNode("fq");
  scene.mRootNode->mNumMeshes = scene.mNumMeshes = unsigned(parts.size());
  scene.mRootNode->mMeshes = new unsigned[parts.size()];
  scene.mMeshes = new aiMesh*[parts.size()];
  add_materials(scene, a.materials, path);
  // Viewers shade a glb without normals flat (or not at all): give it the surface's own.
  const bool has_normals =
      !a.corner_normal.empty() || (a.find_vertex("nx") && a.find_vertex("ny") && a.find_vertex("nz"));
  const std::vector<std::array<float, 3>> computed =
      has_normals ? std::vector<std::array<float, 3>>() : vertex_normals(mesh);
  std::vector<std::string> used;
  bool coloured = false;
  for (size_t i = 0; i < parts.size(); ++i) {
    scene.mRootNode->mMeshes[i] = unsigned(i);
    scene.mMeshes[i] = make_mesh(mesh, parts[i]);
    fill_normals_and_uvs(*scene.mMeshes[i], parts[i], a, computed, used);
    coloured = fill_colours(*scene.mMeshes[i], parts[i], labels, a, colour_clusters);
  }
  if (coloured && !(labels && colour_clusters)) used.insert(used.end(), {"red", "green", "blue", "alpha"});
  std::vector<std::string> lost;
  for (const ElementProperty& p : a.vertex)
    if (std::find(used.begin(), used.end(), p.name) == used.end()) lost.push_back(p.name);
  for (const std::string& phrase : group_property_names(lost)) dropped.push_back("vertex " + phrase);
  for (const ElementProperty& p : a.face) dropped.push_back("face property '" + p.name + "'");
  if (labels)
    dropped.emplace_back(
        coloured && (colour_clusters || !a.find_vertex("red"))
            ? "cluster labels as integers (the vertex colours show the clusters)"
            : "cluster labels (glb has no per-vertex integer property; try --colour-clusters)");
  Assimp::Exporter exporter;
  if (exporter.Export(&scene, "glb2", path) != aiReturn_SUCCESS)
    return invalid_argument("cannot write '" + path + "': " + exporter.GetErrorString());
  return {};
}

}  // namespace fq::io
