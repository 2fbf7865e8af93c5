#include "io/mesh_attributes.h"

#include <array>
#include <cmath>
#include <utility>

#include "common/pair_table.h"

namespace fq::io {

namespace {

constexpr std::pair<ScalarType, const char*> kPlyTypeNames[] = {
    {ScalarType::kInt8, "char"},     {ScalarType::kUInt8, "uchar"},   {ScalarType::kInt16, "short"},
    {ScalarType::kUInt16, "ushort"}, {ScalarType::kInt32, "int"},     {ScalarType::kUInt32, "uint"},
    {ScalarType::kFloat32, "float"}, {ScalarType::kFloat64, "double"}};

// A normal's arithmetic, in float like the engines' Vec3 (kernels/vec3.h, which mesh files do
// not link: they need only the vocabulary).
using Float3 = std::array<float, 3>;
Float3 operator-(const Float3& a, const Float3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Float3 cross(const Float3& a, const Float3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

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
  std::vector<Float3> sum(mesh.num_vertices, Float3{0.f, 0.f, 0.f});
  auto at = [&](uint32_t v) {
    const float* p = mesh.positions + 3 * size_t(v);
    return Float3{p[0], p[1], p[2]};
  };
  for (uint32_t t = 0; t < mesh.num_triangles; ++t) {
    const uint32_t* c = &mesh.triangles[3 * size_t(t)];
    // The cross product's length is twice the area: larger triangles weigh more.
    const Float3 area_normal = cross(at(c[1]) - at(c[0]), at(c[2]) - at(c[0]));
    for (int k = 0; k < 3; ++k) {
      for (int i = 0; i < 3; ++i) sum[c[k]][i] += area_normal[i];
    }
  }
  for (uint32_t v = 0; v < mesh.num_vertices; ++v) {
    const Float3& n_v = sum[v];
    const float len = std::sqrt(n_v[0] * n_v[0] + n_v[1] * n_v[1] + n_v[2] * n_v[2]);
    if (!(len > 0.f) || !std::isfinite(len)) continue;
    for (int i = 0; i < 3; ++i) n[i]->values[v] = n_v[i] / len;
  }
  return true;
}

}  // namespace fq::io
