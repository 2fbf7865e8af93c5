#include "io/assimp_io.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <array>
#include <assimp/Importer.hpp>
#include <map>

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

}  // namespace fq::io
