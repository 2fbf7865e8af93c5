#include "io/surface_normals.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <unordered_map>
#include <utility>

namespace fq::io {

namespace {

// A normal's arithmetic, in float like the engines' Vec3 (kernels/vec3.h, which mesh files do
// not link: they need only the vocabulary).
using Float3 = std::array<float, 3>;
Float3 operator-(const Float3& a, const Float3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Float3 cross(const Float3& a, const Float3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

/// `n` scaled to unit length; false (and `n` untouched) when it has no direction.
bool normalize(Float3& n) {
  const float len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  if (!(len > 0.f) || !std::isfinite(len)) return false;
  for (float& x : n) x /= len;
  return true;
}

/// Each triangle's area normal added to the sum of the group of each of its corners (corner c
/// is in group[c]): with the vertex indices as groups, the vertex normals before normalizing.
std::vector<Float3> sum_area_normals(const MeshView& mesh, const uint32_t* group, size_t num_groups) {
  std::vector<Float3> sum(num_groups, Float3{0.f, 0.f, 0.f});
  auto at = [&](uint32_t v) {
    const float* p = mesh.positions + 3 * size_t(v);
    return Float3{p[0], p[1], p[2]};
  };
  for (size_t t = 0; t < mesh.num_triangles; ++t) {
    const uint32_t* c = &mesh.triangles[3 * t];
    // The cross product's length is twice the area: larger triangles weigh more.
    const Float3 area_normal = cross(at(c[1]) - at(c[0]), at(c[2]) - at(c[0]));
    for (size_t k = 3 * t; k < 3 * t + 3; ++k) {
      for (int i = 0; i < 3; ++i) sum[group[k]][i] += area_normal[i];
    }
  }
  return sum;
}

/// For each value of `c`, the first value equal to it bit for bit: two `vn` lines with one
/// normal are one group, as if the corners shared the line.
std::vector<uint32_t> first_equal_values(const CornerValues& c) {
  std::map<std::array<uint32_t, 3>, uint32_t> first;
  std::vector<uint32_t> out(c.values.size() / 3);
  for (uint32_t i = 0; i < out.size(); ++i) {
    std::array<uint32_t, 3> bits;
    std::memcpy(bits.data(), &c.values[3 * size_t(i)], sizeof bits);
    out[i] = first.try_emplace(bits, i).first->second;
  }
  return out;
}

}  // namespace

std::vector<std::array<float, 3>> vertex_normals(const MeshView& mesh) {
  std::vector<Float3> n = sum_area_normals(mesh, mesh.triangles, mesh.num_vertices);
  for (Float3& v : n) {
    if (!normalize(v)) v = Float3{0.f, 0.f, 0.f};
  }
  return n;
}

bool recompute_normals(const MeshView& mesh, MeshAttributes& attributes) {
  ElementProperty* n[3] = {attributes.find_vertex("nx"), attributes.find_vertex("ny"),
                           attributes.find_vertex("nz")};
  if (!n[0] || !n[1] || !n[2]) return false;
  const std::vector<Float3> sum = sum_area_normals(mesh, mesh.triangles, mesh.num_vertices);
  for (uint32_t v = 0; v < mesh.num_vertices; ++v) {
    Float3 n_v = sum[v];
    if (!normalize(n_v)) continue;
    for (int i = 0; i < 3; ++i) n[i]->values[v] = n_v[i];
  }
  return true;
}

void recompute_corner_normals(const MeshView& mesh, CornerValues& normals) {
  if (normals.empty() || normals.components != 3) return;
  const std::vector<uint32_t> same = first_equal_values(normals);
  std::unordered_map<uint64_t, uint32_t> group_of;  // (vertex, input normal) -> group
  std::vector<uint32_t> group(normals.corners.size());
  std::vector<uint32_t> source;  // per group: its input normal, kept where the group has no area
  for (size_t c = 0; c < group.size(); ++c) {
    const uint32_t value = same[normals.corners[c]];
    const auto [it, added] =
        group_of.try_emplace((uint64_t(mesh.triangles[c]) << 32) | value, uint32_t(source.size()));
    if (added) source.push_back(value);
    group[c] = it->second;
  }
  const std::vector<Float3> sum = sum_area_normals(mesh, group.data(), source.size());
  std::vector<float> values(3 * source.size());
  for (size_t g = 0; g < source.size(); ++g) {
    Float3 n = sum[g];
    if (!normalize(n)) std::memcpy(n.data(), &normals.values[3 * size_t(source[g])], sizeof n);
    std::memcpy(&values[3 * g], n.data(), sizeof n);
  }
  normals.values = std::move(values);
  normals.corners = std::move(group);
}

}  // namespace fq::io
