#include "proto/ply_reader.h"

#include <vector>

#include "draco/core/decoder_buffer.h"
#include "draco/io/ply_property_reader.h"
#include "draco/io/ply_reader.h"
#include "proto/draco_reader.h"
#include "proto/ply_extent_check.h"

namespace fq::io {

namespace {

Status read_vertices(const std::string& path, const draco::PlyElement* vertex, Mesh& out) {
  if (!vertex) return invalid_input("cannot decode '" + path + "': no vertex element");
  const draco::PlyProperty* xyz[3] = {vertex->GetPropertyByName("x"), vertex->GetPropertyByName("y"),
                                      vertex->GetPropertyByName("z")};
  for (const draco::PlyProperty* p : xyz) {
    if (!p || p->is_list()) return invalid_input("'" + path + "' has no x, y, z vertex properties");
  }
  const draco::PlyPropertyReader<float> rx(xyz[0]), ry(xyz[1]), rz(xyz[2]);
  const int n = vertex->num_entries();
  out.positions.resize(3 * size_t(n));
  for (int v = 0; v < n; ++v) {
    out.positions[3 * size_t(v) + 0] = rx.ReadValue(v);
    out.positions[3 * size_t(v) + 1] = ry.ReadValue(v);
    out.positions[3 * size_t(v) + 2] = rz.ReadValue(v);
  }
  return {};
}

Status read_faces(const std::string& path, const draco::PlyElement* face, Mesh& out) {
  if (!face || face->num_entries() == 0) return {};
  const draco::PlyProperty* idx = face->GetPropertyByName("vertex_indices");
  if (!idx) idx = face->GetPropertyByName("vertex_index");
  if (!idx || !idx->is_list()) return invalid_input("'" + path + "' has faces without vertex_indices");
  const draco::PlyPropertyReader<int64_t> reader(idx);
  const int n = face->num_entries();
  const int64_t num_vertices = out.num_vertices();
  out.triangles.resize(3 * size_t(n));
  for (int f = 0; f < n; ++f) {
    if (idx->GetListEntryNumValues(f) != 3)
      return invalid_input("'" + path + "' is not a triangle mesh: face " + std::to_string(f) + " has " +
                           std::to_string(idx->GetListEntryNumValues(f)) + " vertices");
    const int64_t offset = idx->GetListEntryOffset(f);
    for (int k = 0; k < 3; ++k) {
      const int64_t v = reader.ReadValue(static_cast<int>(offset + k));
      if (v < 0 || v >= num_vertices)
        return invalid_input("cannot decode '" + path + "': face " + std::to_string(f) +
                             " references vertex " + std::to_string(v) + " of " +
                             std::to_string(num_vertices));
      out.triangles[3 * size_t(f) + k] = static_cast<uint32_t>(v);
    }
  }
  return {};
}

}  // namespace

Status read_ply(const std::string& path, Mesh& out) {
  std::vector<char> bytes;
  FQ_RETURN_IF_ERROR(read_file_bytes(path, bytes));
  FQ_RETURN_IF_ERROR(check_binary_ply_extent(path, bytes));
  draco::DecoderBuffer buffer;
  buffer.Init(bytes.data(), bytes.size());
  draco::PlyReader reader;
  const draco::Status s = reader.Read(&buffer);
  if (!s.ok()) {
    const std::string& msg = s.error_msg_string();
    return invalid_input("cannot decode '" + path + "': " + (msg.empty() ? "not a valid PLY file" : msg));
  }
  FQ_RETURN_IF_ERROR(read_vertices(path, reader.GetElementByName("vertex"), out));
  return read_faces(path, reader.GetElementByName("face"), out);
}

}  // namespace fq::io
