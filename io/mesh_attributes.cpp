#include "io/mesh_attributes.h"

#include <algorithm>
#include <array>
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

}  // namespace fq::io
