#include "io/mesh_attributes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string_view>
#include <utility>

#include "common/pair_table.h"

namespace fq::io {

namespace {

constexpr std::pair<ScalarType, const char*> kPlyTypeNames[] = {
    {ScalarType::kInt8, "char"},     {ScalarType::kUInt8, "uchar"},   {ScalarType::kInt16, "short"},
    {ScalarType::kUInt16, "ushort"}, {ScalarType::kInt32, "int"},     {ScalarType::kUInt32, "uint"},
    {ScalarType::kFloat32, "float"}, {ScalarType::kFloat64, "double"}};

constexpr std::pair<const char*, const char*> kUvNames[] = {
    {"u", "v"}, {"s", "t"}, {"texture_u", "texture_v"}, {"texture_s", "texture_t"}};

// A normal's arithmetic, in float like the engines' Vec3 (kernels/vec3.h, which mesh files do
// not link: they need only the vocabulary).
using Float3 = std::array<float, 3>;
Float3 operator-(const Float3& a, const Float3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Float3 cross(const Float3& a, const Float3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

/// Property names that warnings name together.
struct PropertyGroup {
  const char* phrase;
  std::array<std::string_view, 8> members;
};
constexpr PropertyGroup kGroups[] = {
    {"normals", {"nx", "ny", "nz"}},
    {"colours", {"red", "green", "blue", "alpha"}},
    {"texture coordinates", {"u", "v", "s", "t", "texture_u", "texture_v", "texture_s", "texture_t"}},
    {"cluster labels", {"label", "cluster_red", "cluster_green", "cluster_blue"}},
};

const PropertyGroup* group_of(std::string_view name) {
  for (const PropertyGroup& g : kGroups) {
    if (!name.empty() && std::find(g.members.begin(), g.members.end(), name) != g.members.end()) return &g;
  }
  return nullptr;
}

}  // namespace

const char* ply_type_name(ScalarType t) { return second_of(kPlyTypeNames, t).value_or("float"); }

const ElementProperty* MeshAttributes::find_vertex(const std::string& name) const {
  for (const ElementProperty& p : vertex) {
    if (p.name == name && !p.is_list) return &p;
  }
  return nullptr;
}

std::array<const ElementProperty*, 2> MeshAttributes::vertex_uv() const {
  for (const auto& [u, v] : kUvNames) {
    if (find_vertex(u) && find_vertex(v)) return {find_vertex(u), find_vertex(v)};
  }
  return {nullptr, nullptr};
}

bool is_label_property(const std::string& name) { return group_of(name) == &kGroups[3]; }

std::vector<std::string> group_property_names(const std::vector<std::string>& names) {
  std::vector<std::string> out;
  std::vector<const PropertyGroup*> seen;
  for (const std::string& name : names) {
    const PropertyGroup* group = group_of(name);
    if (!group) {
      out.push_back("property '" + name + "'");
      continue;
    }
    if (std::find(seen.begin(), seen.end(), group) != seen.end()) continue;
    seen.push_back(group);
    std::string members;
    for (const std::string& n : names) {
      if (group_of(n) == group) members += (members.empty() ? "" : ", ") + n;
    }
    out.push_back(std::string(group->phrase) + " (" + members + ")");
  }
  return out;
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
