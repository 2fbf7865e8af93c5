// What a mesh file holds besides positions and triangles, kept so that a filtered mesh can be
// written back with it: vertex colours, normals, texture coordinates, per-vertex scalars and
// face properties of PLY files.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/mesh_view.h"

namespace fq::io {

/// PLY scalar types (char, uchar, short, ushort, int, uint, float, double).
enum class ScalarType : uint8_t { kInt8, kUInt8, kInt16, kUInt16, kInt32, kUInt32, kFloat32, kFloat64 };

/// PLY's name of `t` ("uchar", "float", ...).
const char* ply_type_name(ScalarType t);

/// One property of every vertex or every face, as read. Values are held as doubles, which
/// represent every PLY scalar type exactly, and written back in `type`.
struct ElementProperty {
  std::string name;
  ScalarType type = ScalarType::kFloat32;
  bool is_list = false;
  ScalarType count_type = ScalarType::kUInt8;  ///< lists only: type of the per-element count
  std::vector<double> values;                  ///< one per element; lists: all items in order
  std::vector<uint32_t> offsets;  ///< lists only: element i's items are [offsets[i], offsets[i+1])
};

/// Values given per triangle corner ("wedges": an OBJ's `vt` and `vn`), so that one vertex
/// may carry several (along a texture seam or a hard edge). A filter moves positions only:
/// texture coordinates stay as they were read; fqfilter recomputes normals
/// (surface_normals.h).
struct CornerValues {
  int components = 0;             ///< 2 (texture coordinates) or 3 (normals)
  std::vector<float> values;      ///< `components` floats per distinct value
  std::vector<uint32_t> corners;  ///< 3 per triangle: the index of each corner's value
  bool empty() const { return corners.empty(); }
};

/// An OBJ's material library and the material of each triangle.
struct Materials {
  std::string library;                ///< the `mtllib` file as a path (absolute, or as given)
  std::vector<std::string> names;     ///< material names by index
  std::vector<uint32_t> of_triangle;  ///< per triangle: an index into names
  bool empty() const { return names.empty(); }
};

struct MeshAttributes {
  std::vector<ElementProperty> vertex;  ///< every vertex property but x, y, z
  std::vector<ElementProperty> face;    ///< every face property but the vertex indices
  CornerValues corner_uv;               ///< OBJ texture coordinates (2 components)
  CornerValues corner_normal;           ///< OBJ normals (3 components)
  Materials materials;
  /// What the reader saw but could not keep, one phrase each ("element 'edge'", "the OBJ's
  /// texture coordinates (vertices are welded)"); the caller warns about each.
  std::vector<std::string> dropped;

  /// The vertex property called `name`, or null.
  ElementProperty* find_vertex(const std::string& name);
  const ElementProperty* find_vertex(const std::string& name) const;
  /// The first pair of vertex properties that are texture coordinates (u, v / s, t /
  /// texture_u, texture_v / texture_s, texture_t), or nulls.
  std::array<const ElementProperty*, 2> vertex_uv() const;
};

/// label, cluster_red, cluster_green, cluster_blue: what fq writes with cluster labels.
bool is_label_property(const std::string& name);

/// Property names as the phrases of warnings, one phrase per group: "normals (nx, ny, nz)",
/// "colours (red, green, blue, alpha)", "texture coordinates (u, v)", and the others named
/// one by one: "property 'quality'". Names in `names`' order, each group where its first
/// member was.
std::vector<std::string> group_property_names(const std::vector<std::string>& names);

}  // namespace fq::io
