#include "proto/mesh_io.h"

#include <algorithm>
#include <cctype>
#include <exception>
#include <filesystem>
#include <new>
#include <stdexcept>
#include <string_view>

#include "proto/draco_reader.h"
#include "proto/drc_writer.h"
#include "proto/ply_reader.h"
#include "proto/ply_writer.h"

namespace fq::io {

namespace {

constexpr std::string_view kReadable[] = {".ply", ".obj", ".stl", ".drc"};

Status read_by_extension(const std::string& path, Mesh& out) {
  const std::string ext = lower_extension(path);
  if (ext == ".ply") return read_ply(path, out);
  if (ext == ".drc") return read_drc(path, out);
  return read_obj_or_stl(path, out);
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

}  // namespace

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

bool is_readable_mesh_file(const std::string& path) {
  const std::string ext = lower_extension(path);
  return std::find(std::begin(kReadable), std::end(kReadable), ext) != std::end(kReadable);
}

Status read_mesh(const std::string& path, Mesh& out) {
  out = Mesh{};
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return io_error("cannot read '" + path + "': no such file");
  if (std::filesystem::is_directory(path, ec)) return io_error("cannot read '" + path + "': is a folder");
  if (!is_readable_mesh_file(path))
    return invalid_argument("cannot read '" + path + "': unsupported extension '" + lower_extension(path) +
                            "' (expected .ply, .obj, .stl or .drc)");
  Status s;
  try {
    s = read_by_extension(path, out);
  } catch (const std::length_error&) {
    // Draco sizes allocations from counts in the file; a corrupt one can ask for too much.
    s = invalid_input("cannot decode '" + path + "': its header announces more data than can be allocated");
  } catch (const std::bad_alloc&) {
    s = invalid_input("cannot decode '" + path + "': out of memory (corrupt header or mesh too large)");
  } catch (const std::exception& e) {
    s = invalid_input("cannot decode '" + path + "': " + e.what());
  }
  if (!s.ok()) out = Mesh{};
  return s;
}

Status write_mesh(const std::string& path, const MeshView& mesh, const uint32_t* labels,
                  uint32_t num_clusters, int drc_position_bits) {
  const std::string ext = lower_extension(path);
  if (ext != ".ply" && ext != ".drc")
    return invalid_argument("cannot write '" + path + "': unsupported output extension '" + ext +
                            "' (expected .ply or .drc)");
  FQ_RETURN_IF_ERROR(check_for_writing(path, mesh, labels, num_clusters));
  if (ext == ".ply") return write_ply(path, mesh, labels);
  if (drc_position_bits < 0 || drc_position_bits > 30)
    return invalid_argument("Draco position bits must be in 0..30 (got " + std::to_string(drc_position_bits) +
                            ")");
  try {
    return write_drc(path, mesh, labels, num_clusters, drc_position_bits);
  } catch (const std::exception& e) {
    return invalid_input("cannot encode '" + path + "' with Draco: " + e.what());
  }
}

}  // namespace fq::io
