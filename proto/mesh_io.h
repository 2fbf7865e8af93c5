// Mesh files in and out. The only file I/O code that talks to Draco.
//   read:  .ply .obj .stl .drc (Draco's readers)
//   write: .ply (our binary writer, with labels and colours) and .drc (Draco encoder)
#pragma once

#include <cstdint>
#include <string>

#include "kernels/mesh_view.h"
#include "common/status.h"

namespace fq::io {

/// Lower-case extension of `path` with its dot (".ply"), or "" when it has none.
std::string lower_extension(const std::string& path);

/// True for the extensions read_mesh accepts (.ply, .obj, .stl, .drc; any case).
bool is_readable_mesh_file(const std::string& path);

/// True for the extensions write_mesh accepts (.ply, .drc; any case).
bool is_writable_mesh_file(const std::string& path);

/// Reads a triangle mesh with Draco. PLY keeps the file's vertex count and order
/// (coincident vertices stay separate) and must have triangle faces only; .drc gives the
/// decoded points; OBJ and STL (binary only) are welded: one vertex per distinct position,
/// so texture or normal seams do not cut the surface (OBJ keeps the order of its `v`
/// lines; Draco fan-triangulates OBJ polygons). Only positions are read.
/// A file with no faces reads fine (out has zero triangles); the engines reject it later.
/// Errors (one line, naming the file): missing file, unsupported extension, decode
/// failure (with Draco's message), no 3D positions, not a triangle mesh (a PLY polygon,
/// a Draco point cloud), a face index out of range.
Status read_mesh(const std::string& path, Mesh& out);

/// Writes `mesh` by extension of `path`:
///  - .ply: binary little-endian, `float x,y,z`; with labels also `uint label` and
///    `uchar red,green,blue` (cluster_color of the label); faces as `list uchar int`.
///  - .drc: Draco, positions quantized to `drc_position_bits` (1..30, or 0 for no
///    quantization); labels as a GENERIC uint32 attribute whose attribute metadata has
///    name = "fq_label", and the geometry metadata entry "fq_num_clusters".
/// `labels` is null or holds one label per vertex, each < num_clusters (checked).
/// Errors: other extensions, bad labels or bits, unopenable or unwritable output.
Status write_mesh(const std::string& path, const MeshView& mesh, const uint32_t* labels,
                  uint32_t num_clusters, int drc_position_bits = 16);

/// Metadata key and value that name the labels attribute in .drc files.
inline constexpr const char* kLabelMetadataKey = "name";
inline constexpr const char* kLabelMetadataName = "fq_label";
inline constexpr const char* kNumClustersMetadataKey = "fq_num_clusters";

}  // namespace fq::io
