// Why we write PLY ourselves: Draco 1.5.5's PlyEncoder silently drops GENERIC attributes,
// so it cannot carry cluster labels, nor the colours, normals, texture coordinates and
// other properties of the input that fqfilter keeps. The format is small: a header and
// little-endian binary blocks.
#include "io/ply_writer.h"

#include <bit>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <vector>

#include "io/cluster_colors.h"

namespace fq::io {

namespace {

/// Calls `f` with a zero of the C++ type that holds `type`'s values.
template <class F>
void with_cpp_type(ScalarType type, F&& f) {
  switch (type) {
    case ScalarType::kInt8:
      return f(int8_t{});
    case ScalarType::kUInt8:
      return f(uint8_t{});
    case ScalarType::kInt16:
      return f(int16_t{});
    case ScalarType::kUInt16:
      return f(uint16_t{});
    case ScalarType::kInt32:
      return f(int32_t{});
    case ScalarType::kUInt32:
      return f(uint32_t{});
    case ScalarType::kFloat32:
      return f(float{});
    case ScalarType::kFloat64:
      return f(double{});
  }
}

/// Appends `value` as the little-endian bytes of `type`, whatever the host order.
void put(std::vector<char>& out, ScalarType type, double value) {
  with_cpp_type(type, [&out, value](auto zero) {
    const auto v = static_cast<decltype(zero)>(value);
    const auto bits = std::bit_cast<std::conditional_t<
        sizeof(v) == 8, uint64_t,
        std::conditional_t<sizeof(v) == 4, uint32_t, std::conditional_t<sizeof(v) == 2, uint16_t, uint8_t>>>>(
        v);
    for (size_t i = 0; i < sizeof(v); ++i) out.push_back(static_cast<char>((bits >> (8 * i)) & 0xffu));
  });
}

ElementProperty scalar(std::string name, ScalarType type, size_t n) {
  ElementProperty p;
  p.name = std::move(name);
  p.type = type;
  p.values.resize(n);
  return p;
}

/// A colour channel of `type`: floats hold 0..1, integers 0..255.
double channel(uint8_t c, ScalarType type) {
  return type == ScalarType::kFloat32 || type == ScalarType::kFloat64 ? c / 255.0 : c;
}

/// Fills colour channel `k` (0 red, 1 green, 2 blue) of column `c` from the labels' colours.
void fill_cluster_colour(ElementProperty& c, const std::vector<Rgb8>& colours, int k) {
  for (size_t v = 0; v < c.values.size(); ++v) {
    const Rgb8 colour = colours[v];
    c.values[v] = channel(k == 0 ? colour.r : k == 1 ? colour.g : colour.b, c.type);
  }
}

std::vector<ElementProperty> vertex_columns(const MeshView& mesh, const uint32_t* labels,
                                            const MeshAttributes* a, bool colour_clusters) {
  const size_t n = mesh.num_vertices;
  std::vector<ElementProperty> cols;
  for (int k = 0; k < 3; ++k) {
    cols.push_back(scalar(std::string(1, char('x' + k)), ScalarType::kFloat32, n));
    for (size_t v = 0; v < n; ++v) cols.back().values[v] = mesh.positions[3 * v + k];
  }
  for (const ElementProperty& p : a ? a->vertex : std::vector<ElementProperty>{}) {
    // New labels replace those of an earlier run.
    if (!labels || !is_label_property(p.name)) cols.push_back(p);
  }
  if (!labels) return cols;
  std::vector<Rgb8> colours(n);  // once per vertex: cluster_color is an HSV conversion
  for (size_t v = 0; v < n; ++v) colours[v] = cluster_color(labels[v]);
  const char* rgb[3] = {"red", "green", "blue"};
  const bool has_rgb = a && a->find_vertex(rgb[0]) && a->find_vertex(rgb[1]) && a->find_vertex(rgb[2]);
  for (int k = 0; k < 3; ++k) {
    if (has_rgb && !colour_clusters) continue;
    if (!has_rgb) cols.push_back(scalar(rgb[k], ScalarType::kUInt8, n));
    for (ElementProperty& c : cols) {
      if (c.name == rgb[k] && !c.is_list) fill_cluster_colour(c, colours, k);
    }
  }
  cols.push_back(scalar("label", ScalarType::kUInt32, n));
  for (size_t v = 0; v < n; ++v) cols.back().values[v] = labels[v];
  for (int k = 0; k < 3; ++k) {
    cols.push_back(scalar(std::string("cluster_") + rgb[k], ScalarType::kUInt8, n));
    fill_cluster_colour(cols.back(), colours, k);
  }
  return cols;
}

std::vector<ElementProperty> face_columns(const MeshView& mesh, const MeshAttributes* a) {
  ElementProperty idx;
  idx.name = "vertex_indices";
  idx.type = ScalarType::kInt32;  // PLY "int": the index type every reader expects
  idx.is_list = true;
  idx.values.assign(mesh.triangles, mesh.triangles + 3 * size_t(mesh.num_triangles));
  for (uint32_t t = 0; t <= mesh.num_triangles; ++t) idx.offsets.push_back(3 * t);
  std::vector<ElementProperty> cols{std::move(idx)};
  if (a) cols.insert(cols.end(), a->face.begin(), a->face.end());
  return cols;
}

void header_element(std::ostringstream& h, const char* name, size_t n,
                    const std::vector<ElementProperty>& cols) {
  h << "element " << name << " " << n << "\n";
  for (const ElementProperty& c : cols) {
    h << "property ";
    if (c.is_list) h << "list " << ply_type_name(c.count_type) << " ";
    h << ply_type_name(c.type) << " " << c.name << "\n";
  }
}

void body_element(std::vector<char>& out, size_t n, const std::vector<ElementProperty>& cols) {
  for (size_t i = 0; i < n; ++i) {
    for (const ElementProperty& c : cols) {
      if (!c.is_list) {
        put(out, c.type, c.values[i]);
        continue;
      }
      put(out, c.count_type, c.offsets[i + 1] - c.offsets[i]);
      for (uint32_t k = c.offsets[i]; k < c.offsets[i + 1]; ++k) put(out, c.type, c.values[k]);
    }
  }
}

}  // namespace

Status write_ply(const std::string& path, const MeshView& mesh, const uint32_t* labels,
                 const MeshAttributes* attributes, bool colour_clusters) {
  if (mesh.num_vertices > uint32_t(std::numeric_limits<int32_t>::max()))
    return invalid_argument("cannot write '" + path + "': too many vertices for a PLY int index");
  const std::vector<ElementProperty> vcols = vertex_columns(mesh, labels, attributes, colour_clusters);
  const std::vector<ElementProperty> fcols = face_columns(mesh, attributes);
  std::ostringstream h;
  h << "ply\nformat binary_little_endian 1.0\ncomment written by fq\n";
  header_element(h, "vertex", mesh.num_vertices, vcols);
  header_element(h, "face", mesh.num_triangles, fcols);
  h << "end_header\n";
  std::vector<char> body;
  body_element(body, mesh.num_vertices, vcols);
  body_element(body, mesh.num_triangles, fcols);
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  if (!f) return io_error("cannot open '" + path + "' for writing: " + std::strerror(errno));
  const std::string hs = h.str();
  f.write(hs.data(), std::streamsize(hs.size()));
  f.write(body.data(), std::streamsize(body.size()));
  f.close();
  if (!f) return io_error("cannot write '" + path + "': write failed (disk full?)");
  return {};
}

}  // namespace fq::io
