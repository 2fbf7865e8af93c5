#include "io/obj_corners.h"

#include <filesystem>

#include "draco/mesh/mesh.h"
#include "draco/metadata/geometry_metadata.h"

namespace fq::io {

namespace {

/// The distinct values of `att` and each triangle corner's index into them.
CornerValues corner_values(const draco::Mesh& dm, const draco::PointAttribute& att, int components) {
  CornerValues c;
  c.components = components;
  c.values.resize(att.size() * size_t(components));
  for (uint32_t i = 0; i < att.size(); ++i)
    att.ConvertValue<float>(draco::AttributeValueIndex(i), components, &c.values[size_t(i) * components]);
  c.corners.resize(3 * size_t(dm.num_faces()));
  for (uint32_t f = 0; f < dm.num_faces(); ++f) {
    const draco::Mesh::Face& face = dm.face(draco::FaceIndex(f));
    for (int k = 0; k < 3; ++k) c.corners[3 * size_t(f) + k] = att.mapped_index(face[k]).value();
  }
  return c;
}

/// Draco's ObjDecoder puts materials in a GENERIC attribute whose metadata names it
/// "material", maps each material name to its value, and gives the library as "file_name".
Materials materials_of(const draco::Mesh& dm, const std::string& path) {
  Materials m;
  const draco::AttributeMetadata* md = dm.GetAttributeMetadataByStringEntry("name", "material");
  const draco::PointAttribute* att = md ? dm.GetAttributeByUniqueId(md->att_unique_id()) : nullptr;
  if (!att) return m;
  for (const auto& [key, value] : md->entries()) {
    int32_t id = 0;
    if (key == "name" || key == "file_name" || !md->GetEntryInt(key, &id) || id < 0) continue;
    if (size_t(id) >= m.names.size()) m.names.resize(size_t(id) + 1);
    m.names[size_t(id)] = key;
  }
  if (std::string library; md->GetEntryString("file_name", &library) && !library.empty())
    m.library = (std::filesystem::absolute(path).parent_path() / library).lexically_normal().string();
  m.of_triangle.resize(dm.num_faces());
  for (uint32_t f = 0; f < dm.num_faces(); ++f) {
    int32_t id = 0;
    att->ConvertValue<int32_t>(att->mapped_index(dm.face(draco::FaceIndex(f))[0]), 1, &id);
    m.of_triangle[f] = id >= 0 && size_t(id) < m.names.size() ? uint32_t(id) : 0;
  }
  if (m.names.empty()) m.names.emplace_back("default");
  return m;
}

}  // namespace

void keep_obj_corners(const draco::Mesh& dm, const std::string& path, MeshAttributes& attributes) {
  if (const draco::PointAttribute* uv = dm.GetNamedAttribute(draco::GeometryAttribute::TEX_COORD))
    attributes.corner_uv = corner_values(dm, *uv, 2);
  if (const draco::PointAttribute* n = dm.GetNamedAttribute(draco::GeometryAttribute::NORMAL))
    attributes.corner_normal = corner_values(dm, *n, 3);
  attributes.materials = materials_of(dm, path);
}

}  // namespace fq::io
