#include "python/mesh_dict.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "python/numpy_mesh.h"

namespace fq::py {

namespace {

using FloatArray = pyb::array_t<float, pyb::array::c_style | pyb::array::forcecast>;

constexpr const char* kColourNames[] = {"red", "green", "blue", "alpha"};
constexpr const char* kNormalNames[] = {"nx", "ny", "nz"};

template <size_t N>
bool one_of(const char* const (&names)[N], const std::string& name) {
  return std::find(std::begin(names), std::end(names), name) != std::end(names);
}

bool is_integer(io::ScalarType t) { return t != io::ScalarType::kFloat32 && t != io::ScalarType::kFloat64; }

/// The named vertex properties as one float32 (n, names) array; none when one is missing.
pyb::object columns(const std::vector<const io::ElementProperty*>& props, size_t n, bool colours) {
  for (const io::ElementProperty* p : props) {
    if (!p) return pyb::none();
  }
  pyb::array_t<float> out({ssize_t(n), ssize_t(props.size())});
  float* o = out.mutable_data();
  for (size_t c = 0; c < props.size(); ++c) {
    const double scale = colours && is_integer(props[c]->type) ? 1.0 / 255.0 : 1.0;
    for (size_t v = 0; v < n; ++v) o[v * props.size() + c] = float(props[c]->values[v] * scale);
  }
  return out;
}

pyb::object corner_array(const io::CornerValues& c, size_t num_triangles) {
  if (c.empty()) return pyb::none();
  const auto k = ssize_t(c.components);
  pyb::array_t<float> out({ssize_t(num_triangles), ssize_t(3), k});
  float* o = out.mutable_data();
  for (size_t i = 0; i < c.corners.size(); ++i)
    std::copy_n(&c.values[size_t(c.corners[i]) * k], k, o + i * k);
  return out;
}

/// `key`'s array as float32 of `shape` (-1: 3 or 4); nullopt when absent or None.
std::optional<FloatArray> optional_array(const pyb::dict& d, const char* key, std::vector<ssize_t> shape) {
  if (!d.contains(key) || d[key].is_none()) return std::nullopt;
  FloatArray a = FloatArray::ensure(d[key]);
  bool ok = a && a.ndim() == ssize_t(shape.size());
  for (size_t i = 0; ok && i < shape.size(); ++i)
    ok = shape[i] < 0 ? (a.shape(ssize_t(i)) == 3 || a.shape(ssize_t(i)) == 4)
                      : a.shape(ssize_t(i)) == shape[i];
  if (!ok) {
    std::string want = "(";
    for (size_t i = 0; i < shape.size(); ++i)
      want += (i ? ", " : "") + (shape[i] < 0 ? std::string("3 or 4") : std::to_string(shape[i]));
    throw pyb::value_error(std::string(key) + " must have shape " + want + ")");
  }
  return a;
}

void add_columns(io::MeshAttributes& out, const FloatArray& a, const char* const* names,
                 io::ScalarType type) {
  const size_t n = size_t(a.shape(0)), k = size_t(a.shape(1));
  for (size_t c = 0; c < k; ++c) {
    io::ElementProperty p;
    p.name = names[c];
    p.type = type;
    p.values.resize(n);
    for (size_t v = 0; v < n; ++v) {
      const double x = a.data()[v * k + c];
      p.values[v] = type == io::ScalarType::kUInt8 ? std::clamp(std::round(x * 255.0), 0.0, 255.0) : x;
    }
    out.vertex.push_back(std::move(p));
  }
}

io::CornerValues corners_of(const FloatArray& a) {
  io::CornerValues c;
  c.components = int(a.shape(2));
  c.values.assign(a.data(), a.data() + a.size());
  c.corners.resize(size_t(a.shape(0)) * 3);
  for (size_t i = 0; i < c.corners.size(); ++i) c.corners[i] = uint32_t(i);
  return c;
}

}  // namespace

pyb::dict mesh_dict(const Mesh& mesh, const io::MeshAttributes& a) {
  const size_t n = mesh.num_vertices(), m = mesh.num_triangles();
  pyb::array_t<float> v({ssize_t(n), ssize_t(3)});
  std::copy(mesh.positions.begin(), mesh.positions.end(), v.mutable_data());
  pyb::dict d;
  d["vertices"] = v;
  d["faces"] = faces_array(mesh.triangles);
  std::vector<const io::ElementProperty*> rgb;
  for (const char* c : kColourNames) rgb.push_back(a.find_vertex(c));
  if (!rgb.back()) rgb.pop_back();  // alpha is optional
  d["colors"] = columns(rgb, n, true);
  std::vector<const io::ElementProperty*> normals;
  for (const char* c : kNormalNames) normals.push_back(a.find_vertex(c));
  d["normals"] = columns(normals, n, false);
  const auto uv = a.vertex_uv();
  d["uvs"] = columns({uv[0], uv[1]}, n, false);
  d["corner_uvs"] = corner_array(a.corner_uv, m);
  d["corner_normals"] = corner_array(a.corner_normal, m);
  const io::ElementProperty* label = a.find_vertex("label");
  if (label) {
    std::vector<uint32_t> labels(label->values.begin(), label->values.end());
    d["labels"] = labels_array(labels);
  } else {
    d["labels"] = pyb::none();
  }
  return d;
}

std::vector<std::string> not_carried(const io::MeshAttributes& a) {
  std::vector<std::string> out = a.dropped;
  const auto uv = a.vertex_uv();
  std::vector<std::string> names;
  for (const io::ElementProperty& p : a.vertex) {
    const bool carried = !p.is_list && (one_of(kColourNames, p.name) || one_of(kNormalNames, p.name) ||
                                        &p == uv[0] || &p == uv[1] || io::is_label_property(p.name));
    if (!carried) names.push_back(p.name);
  }
  for (const std::string& phrase : io::group_property_names(names)) out.push_back("vertex " + phrase);
  for (const io::ElementProperty& p : a.face) out.push_back("face property '" + p.name + "'");
  if (!a.materials.empty())
    out.push_back("the materials" +
                  (a.materials.library.empty() ? std::string() : " of '" + a.materials.library + "'") +
                  " (fqfilter keeps them; an fq.Mesh has no place for them)");
  return out;
}

io::MeshAttributes attributes_of(const pyb::dict& d, size_t n, size_t m) {
  io::MeshAttributes out;
  if (const auto c = optional_array(d, "colors", {ssize_t(n), -1}))
    add_columns(out, *c, kColourNames, io::ScalarType::kUInt8);
  if (const auto a = optional_array(d, "normals", {ssize_t(n), 3}))
    add_columns(out, *a, kNormalNames, io::ScalarType::kFloat32);
  static constexpr const char* kUv[] = {"u", "v"};
  if (const auto a = optional_array(d, "uvs", {ssize_t(n), 2}))
    add_columns(out, *a, kUv, io::ScalarType::kFloat32);
  if (const auto a = optional_array(d, "corner_uvs", {ssize_t(m), 3, 2})) out.corner_uv = corners_of(*a);
  if (const auto a = optional_array(d, "corner_normals", {ssize_t(m), 3, 3}))
    out.corner_normal = corners_of(*a);
  return out;
}

}  // namespace fq::py
