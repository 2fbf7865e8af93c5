#include "proto/mesh_attributes.h"

#include <cmath>
#include <utility>

#include "common/pair_table.h"
#include "kernels/vec3.h"

namespace fq::io {

namespace {

constexpr std::pair<ScalarType, const char*> kPlyTypeNames[] = {
    {ScalarType::kInt8, "char"},     {ScalarType::kUInt8, "uchar"},   {ScalarType::kInt16, "short"},
    {ScalarType::kUInt16, "ushort"}, {ScalarType::kInt32, "int"},     {ScalarType::kUInt32, "uint"},
    {ScalarType::kFloat32, "float"}, {ScalarType::kFloat64, "double"}};

}  // namespace

const char* ply_type_name(ScalarType t) { return second_of(kPlyTypeNames, t).value_or("float"); }

const ElementProperty* MeshAttributes::find_vertex(const std::string& name) const {
  for (const ElementProperty& p : vertex) {
    if (p.name == name && !p.is_list) return &p;
  }
  return nullptr;
}

ElementProperty* MeshAttributes::find_vertex(const std::string& name) {
  return const_cast<ElementProperty*>(static_cast<const MeshAttributes*>(this)->find_vertex(name));
}

bool recompute_normals(const MeshView& mesh, MeshAttributes& attributes) {
  ElementProperty* n[3] = {attributes.find_vertex("nx"), attributes.find_vertex("ny"),
                           attributes.find_vertex("nz")};
  if (!n[0] || !n[1] || !n[2]) return false;
  std::vector<Vec3> sum(mesh.num_vertices, Vec3{0.f, 0.f, 0.f});
  auto at = [&](uint32_t v) {
    return Vec3{mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]};
  };
  for (uint32_t t = 0; t < mesh.num_triangles; ++t) {
    const uint32_t* c = &mesh.triangles[3 * size_t(t)];
    // The cross product's length is twice the area: larger triangles weigh more.
    const Vec3 area_normal = cross(at(c[1]) - at(c[0]), at(c[2]) - at(c[0]));
    for (int k = 0; k < 3; ++k) sum[c[k]] = sum[c[k]] + area_normal;
  }
  for (uint32_t v = 0; v < mesh.num_vertices; ++v) {
    const float len = std::sqrt(dot(sum[v], sum[v]));
    if (!(len > 0.f) || !std::isfinite(len)) continue;
    n[0]->values[v] = sum[v].x / len;
    n[1]->values[v] = sum[v].y / len;
    n[2]->values[v] = sum[v].z / len;
  }
  return true;
}

}  // namespace fq::io
