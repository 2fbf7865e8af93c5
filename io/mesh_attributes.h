// What a mesh file holds besides positions and triangles, kept so that a filtered mesh can be
// written back with it: vertex colours, normals, texture coordinates, per-vertex scalars and
// face properties of PLY files.
#pragma once

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

struct MeshAttributes {
  std::vector<ElementProperty> vertex;  ///< every vertex property but x, y, z
  std::vector<ElementProperty> face;    ///< every face property but the vertex indices
  /// What the reader saw but could not keep, one phrase each ("element 'edge'", "the OBJ's
  /// texture coordinates (vertices are welded)"); the caller warns about each.
  std::vector<std::string> dropped;

  /// The vertex property called `name`, or null.
  ElementProperty* find_vertex(const std::string& name);
  const ElementProperty* find_vertex(const std::string& name) const;
};

/// Overwrites the nx, ny, nz vertex properties (when all three are there) with the
/// area-weighted normals of `mesh`'s triangles: normals of a moved surface must follow it.
/// A vertex on no non-degenerate triangle keeps its old normal. Returns whether it did.
bool recompute_normals(const MeshView& mesh, MeshAttributes& attributes);

}  // namespace fq::io
