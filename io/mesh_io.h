// Mesh files in and out; the only file I/O code that talks to Draco and assimp.
//   read:  .ply .obj .stl .drc (Draco's readers; ASCII STL through assimp)
//   write: .ply (our binary writer: labels, colours, every kept property), .drc (Draco),
//          .obj (our writer: the input's material library kept) and .glb (assimp)
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "common/status.h"
#include "core/mesh_view.h"
#include "io/mesh_attributes.h"

namespace fq::io {

/// Lower-case extension of `path` with its dot (".ply"), or "" when it has none.
std::string lower_extension(const std::string& path);

/// True for the extensions read_mesh accepts (.ply, .obj, .stl, .drc; any case).
bool is_readable_mesh_file(const std::string& path);

/// True for the extensions write_mesh accepts (.ply, .drc, .obj, .glb; any case).
bool is_writable_mesh_file(const std::string& path);

/// "(expected .ply, .obj, .stl or .drc)" / "(expected .ply, .drc, .obj or .glb)": the tail of
/// every unsupported-extension message.
std::string expected_read_extensions();
std::string expected_write_extensions();

/// Reads a triangle mesh; polygons become the fans of their triangles in every format. PLY
/// keeps the file's vertex count and order (coincident vertices stay separate); .drc gives
/// the decoded points; OBJ and STL (binary through Draco, ASCII through assimp) are welded:
/// one vertex per distinct position, so texture or normal seams do not cut the surface (OBJ
/// keeps the order of its `v` lines).
/// With `attributes`, what the file carries besides is kept there: a PLY's other vertex and
/// face properties (colours, normals, texture coordinates, scalars; a polygon's face values
/// go to each of its triangles), a .drc's normals, colours, texture coordinates and labels
/// (as vertex properties), an OBJ's per-corner texture coordinates and normals and its
/// materials. What cannot be kept (other PLY elements, other Draco attributes) is named in
/// attributes->dropped.
/// A file with no faces reads fine (out has zero triangles); the engines reject it later.
/// Errors (one line, naming the file): missing file, unsupported extension, decode
/// failure (with the library's message), no 3D positions, not a triangle mesh (a PLY
/// polygon, a Draco point cloud), a face index out of range.
Status read_mesh(const std::string& path, Mesh& out, MeshAttributes* attributes = nullptr);

struct WriteOptions {
  int drc_position_bits = 16;                  ///< .drc: 1..30, or 0 for no quantization
  const MeshAttributes* attributes = nullptr;  ///< properties to write back (one value per vertex/face)
  bool colour_clusters = false;                ///< cluster colours replace the input's colours
};

/// Writes `mesh` by extension of `path`:
///  - .ply: binary little-endian, `float x,y,z`, the kept vertex properties; with labels
///    also `uint label`, `uchar cluster_red,cluster_green,cluster_blue` and the cluster
///    colours as `red,green,blue` unless the input had colours (see write_ply); faces as
///    `list uchar int vertex_indices` plus the kept face properties.
///    Per-corner texture coordinates become the face list `texcoord` (MeshLab's).
///  - .drc: Draco, positions quantized; labels as a GENERIC uint32 attribute whose
///    attribute metadata has name = "fq_label", and the geometry metadata entry
///    "fq_num_clusters"; normals, colours and texture coordinates as Draco's NORMAL, COLOR
///    and TEX_COORD attributes (per vertex).
///  - .obj: normals and texture coordinates (per corner when the input had them), the
///    input's material library and each triangle's material (obj_writer.h).
///  - .glb: assimp; normals, texture coordinates, vertex colours and materials.
/// What the format cannot hold is named in `dropped` (when given), one phrase a group.
/// `labels` is null or holds one label per vertex, each < num_clusters (checked).
/// Errors: other extensions, bad labels, bits or attributes, unopenable or unwritable output.
Status write_mesh(const std::string& path, const MeshView& mesh, const uint32_t* labels,
                  uint32_t num_clusters, const WriteOptions& options,
                  std::vector<std::string>* dropped = nullptr);

/// write_mesh without attributes.
Status write_mesh(const std::string& path, const MeshView& mesh, const uint32_t* labels,
                  uint32_t num_clusters, int drc_position_bits = 16);

/// Metadata key and value that name the labels attribute in .drc files.
inline constexpr const char* kLabelMetadataKey = "name";
inline constexpr const char* kLabelMetadataName = "fq_label";
inline constexpr const char* kNumClustersMetadataKey = "fq_num_clusters";

}  // namespace fq::io
