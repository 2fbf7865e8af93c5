#include "io/mesh_io.h"

#include <algorithm>
#include <cctype>
#include <exception>
#include <filesystem>
#include <new>
#include <stdexcept>
#include <string_view>

#include "io/assimp_io.h"
#include "io/draco_reader.h"
#include "io/drc_writer.h"
#include "io/glb_writer.h"
#include "io/obj_writer.h"
#include "io/ply_reader.h"
#include "io/ply_writer.h"

namespace fq::io {

namespace {

constexpr std::string_view kReadable[] = {".ply", ".obj", ".stl", ".drc"};
constexpr std::string_view kWritable[] = {".ply", ".drc", ".obj", ".glb"};

template <size_t N>
bool one_of(const std::string& ext, const std::string_view (&list)[N]) {
  return std::find(std::begin(list), std::end(list), ext) != std::end(list);
}

template <size_t N>
std::string expected(const std::string_view (&list)[N]) {
  std::string s = "(expected ";
  for (size_t i = 0; i < N; ++i) s += std::string(list[i]) + (i + 2 < N ? ", " : i + 2 == N ? " or " : ")");
  return s;
}

Status read_by_extension(const std::string& path, Mesh& out, MeshAttributes* attributes) {
  const std::string ext = lower_extension(path);
  if (ext == ".ply") return read_ply(path, out, attributes);
  if (ext == ".drc") return read_drc(path, out, attributes);
  if (ext == ".stl" && is_ascii_stl(path)) return read_ascii_stl(path, out);
  return read_obj_or_stl(path, out, attributes);
}

/// Every kept property has one value (or list) per vertex or face of `mesh`.
Status check_attributes(const std::string& path, const MeshView& mesh, const MeshAttributes& a) {
  for (const auto* list : {&a.vertex, &a.face}) {
    const size_t n = list == &a.vertex ? mesh.num_vertices : mesh.num_triangles;
    for (const ElementProperty& p : *list) {
      const bool ok =
          p.is_list ? p.offsets.size() == n + 1 && p.offsets.back() == p.values.size() : p.values.size() == n;
      if (!ok)
        return invalid_argument("cannot write '" + path + "': property '" + p.name +
                                "' does not match the mesh");
    }
  }
  const size_t corners = 3 * size_t(mesh.num_triangles);
  for (const CornerValues* c : {&a.corner_uv, &a.corner_normal}) {
    const size_t values = c->components > 0 ? c->values.size() / size_t(c->components) : 0;
    if (!c->empty() && (c->corners.size() != corners || std::any_of(c->corners.begin(), c->corners.end(),
                                                                    [&](uint32_t i) { return i >= values; })))
      return invalid_argument("cannot write '" + path + "': per-corner values do not match the mesh");
  }
  const Materials& m = a.materials;
  if (!m.empty() && (m.of_triangle.size() != mesh.num_triangles ||
                     std::any_of(m.of_triangle.begin(), m.of_triangle.end(),
                                 [&](uint32_t i) { return i >= m.names.size(); })))
    return invalid_argument("cannot write '" + path + "': triangle materials do not match the mesh");
  return {};
}

Status check_for_writing(const std::string& path, const MeshView& mesh, const uint32_t* labels,
                         uint32_t num_clusters) {
  for (uint64_t i = 0; i < uint64_t(mesh.num_triangles) * 3; ++i) {
    if (mesh.triangles[i] >= mesh.num_vertices)
      return invalid_argument("cannot write '" + path + "': triangle " + std::to_string(i / 3) +
                              " references a missing vertex");
  }
  if (!labels) return {};
  for (uint32_t v = 0; v < mesh.num_vertices; ++v) {
    if (labels[v] >= num_clusters)
      return invalid_argument("cannot write '" + path + "': vertex " + std::to_string(v) + " has label " +
                              std::to_string(labels[v]) + " but there are " + std::to_string(num_clusters) +
                              " clusters");
  }
  return {};
}

/// Names what of an OBJ's corners and materials a format cannot hold, and why.
void name_corner_values(const MeshAttributes& a, const char* why, std::vector<std::string>& dropped) {
  if (!a.corner_uv.empty()) dropped.push_back(std::string("per-corner texture coordinates (") + why + ")");
  if (!a.corner_normal.empty()) dropped.push_back(std::string("per-corner normals (") + why + ")");
  // (a filter moves positions only, so a format without them loses nothing else)
  if (!a.materials.empty())
    dropped.push_back("the materials" +
                      (a.materials.library.empty() ? std::string() : " of '" + a.materials.library + "'") +
                      " (no material library in this format)");
}

/// `a` for a PLY: per-corner texture coordinates as the face list `texcoord` (u, v of each
/// corner, MeshLab's convention) unless the faces already carry one.
MeshAttributes ply_attributes(const MeshAttributes& a, std::vector<std::string>& dropped) {
  MeshAttributes out = a;
  const bool has_texcoord = std::any_of(a.face.begin(), a.face.end(),
                                        [](const ElementProperty& p) { return p.name == "texcoord"; });
  if (!a.corner_uv.empty() && !has_texcoord) {
    ElementProperty t;
    t.name = "texcoord";
    t.is_list = true;
    t.offsets.push_back(0);
    for (size_t c = 0; c < a.corner_uv.corners.size(); ++c) {
      const float* uv = &a.corner_uv.values[2 * size_t(a.corner_uv.corners[c])];
      t.values.insert(t.values.end(), {uv[0], uv[1]});
      if (c % 3 == 2) t.offsets.push_back(uint32_t(t.values.size()));
    }
    out.face.push_back(std::move(t));
    out.corner_uv = CornerValues{};
  }
  name_corner_values(out, "PLY has no place for them", dropped);
  return out;
}

}  // namespace

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

bool is_readable_mesh_file(const std::string& path) { return one_of(lower_extension(path), kReadable); }
bool is_writable_mesh_file(const std::string& path) { return one_of(lower_extension(path), kWritable); }
std::string expected_read_extensions() { return expected(kReadable); }
std::string expected_write_extensions() { return expected(kWritable); }

Status read_mesh(const std::string& path, Mesh& out, MeshAttributes* attributes) {
  out = Mesh{};
  if (attributes) *attributes = MeshAttributes{};
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return io_error("cannot read '" + path + "': no such file");
  if (std::filesystem::is_directory(path, ec)) return io_error("cannot read '" + path + "': is a folder");
  if (!is_readable_mesh_file(path))
    return invalid_argument("cannot read '" + path + "': unsupported extension '" + lower_extension(path) +
                            "' " + expected_read_extensions());
  Status s;
  try {
    s = read_by_extension(path, out, attributes);
  } catch (const std::length_error&) {
    // Draco sizes allocations from counts in the file; a corrupt one can ask for too much.
    s = invalid_input("cannot decode '" + path + "': its header announces more data than can be allocated");
  } catch (const std::bad_alloc&) {
    s = invalid_input("cannot decode '" + path + "': out of memory (corrupt header or mesh too large)");
  } catch (const std::exception& e) {
    s = invalid_input("cannot decode '" + path + "': " + e.what());
  }
  if (!s.ok()) {
    out = Mesh{};
    if (attributes) *attributes = MeshAttributes{};
  }
  return s;
}

Status write_mesh(const std::string& path, const MeshView& mesh, const uint32_t* labels,
                  uint32_t num_clusters, const WriteOptions& options, std::vector<std::string>* dropped) {
  const std::string ext = lower_extension(path);
  if (!is_writable_mesh_file(path))
    return invalid_argument("cannot write '" + path + "': unsupported output extension '" + ext + "' " +
                            expected_write_extensions());
  FQ_RETURN_IF_ERROR(check_for_writing(path, mesh, labels, num_clusters));
  const MeshAttributes* a = options.attributes;
  if (a) {
    if (Status s = check_attributes(path, mesh, *a); !s.ok()) return s;
  }
  std::vector<std::string> ignored;
  std::vector<std::string>& lost = dropped ? *dropped : ignored;
  try {
    if (ext == ".ply") {
      const MeshAttributes with_corners = a ? ply_attributes(*a, lost) : MeshAttributes{};
      return write_ply(path, mesh, labels, a ? &with_corners : nullptr, options.colour_clusters);
    }
    if (ext == ".obj") return write_obj(path, mesh, labels, a, lost);
    if (ext == ".glb") return write_glb(path, mesh, labels, a, options.colour_clusters, lost);
    if (options.drc_position_bits < 0 || options.drc_position_bits > 30)
      return invalid_argument("Draco position bits must be in 0..30 (got " +
                              std::to_string(options.drc_position_bits) + ")");
    if (a) name_corner_values(*a, "a .drc holds values per vertex", lost);
    return write_drc(path, mesh, labels, num_clusters, options.drc_position_bits, a, lost);
  } catch (const std::exception& e) {
    return invalid_input("cannot encode '" + path + "': " + e.what());
  }
}

Status write_mesh(const std::string& path, const MeshView& mesh, const uint32_t* labels,
                  uint32_t num_clusters, int drc_position_bits) {
  WriteOptions options;
  options.drc_position_bits = drc_position_bits;
  return write_mesh(path, mesh, labels, num_clusters, options);
}

}  // namespace fq::io
