// Why we write PLY ourselves: Draco 1.5.5's PlyEncoder silently drops GENERIC attributes,
// so it cannot carry cluster labels, and its output has no colours for viewers. The
// format we need is small: a fixed header and two little-endian binary blocks.
#include "proto/ply_writer.h"

#include <bit>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <vector>

#include "proto/cluster_colors.h"

namespace fq::io {

namespace {

/// Appends the little-endian bytes of a 4-byte value, whatever the host order.
template <typename T>
void put_le32(std::vector<char>& out, T value) {
  static_assert(sizeof(T) == 4);
  const uint32_t bits = std::bit_cast<uint32_t>(value);
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((bits >> (8 * i)) & 0xffu));
}

std::string header(const MeshView& mesh, bool with_labels) {
  std::ostringstream h;
  h << "ply\nformat binary_little_endian 1.0\ncomment written by fq\n"
    << "element vertex " << mesh.num_vertices << "\n"
    << "property float x\nproperty float y\nproperty float z\n";
  if (with_labels)
    h << "property uint label\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n";
  h << "element face " << mesh.num_triangles << "\n"
    << "property list uchar int vertex_indices\nend_header\n";
  return h.str();
}

std::vector<char> body(const MeshView& mesh, const uint32_t* labels) {
  std::vector<char> out;
  out.reserve(size_t(mesh.num_vertices) * (labels ? 19 : 12) + size_t(mesh.num_triangles) * 13);
  for (uint32_t v = 0; v < mesh.num_vertices; ++v) {
    for (int k = 0; k < 3; ++k) put_le32(out, mesh.positions[3 * size_t(v) + k]);
    if (!labels) continue;
    put_le32(out, labels[v]);
    const Rgb8 c = cluster_color(labels[v]);
    out.insert(out.end(), {static_cast<char>(c.r), static_cast<char>(c.g), static_cast<char>(c.b)});
  }
  for (uint32_t t = 0; t < mesh.num_triangles; ++t) {
    out.push_back(3);
    for (int k = 0; k < 3; ++k) put_le32(out, static_cast<int32_t>(mesh.triangles[3 * size_t(t) + k]));
  }
  return out;
}

}  // namespace

Status write_ply(const std::string& path, const MeshView& mesh, const uint32_t* labels) {
  // Indices are written as PLY "int" (signed 32-bit), the type every reader expects.
  if (mesh.num_vertices > uint32_t(std::numeric_limits<int32_t>::max()))
    return invalid_argument("cannot write '" + path + "': too many vertices for a PLY int index");
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  if (!f) return io_error("cannot open '" + path + "' for writing: " + std::strerror(errno));
  const std::string h = header(mesh, labels != nullptr);
  const std::vector<char> b = body(mesh, labels);
  f.write(h.data(), std::streamsize(h.size()));
  f.write(b.data(), std::streamsize(b.size()));
  f.close();
  if (!f) return io_error("cannot write '" + path + "': write failed (disk full?)");
  return {};
}

}  // namespace fq::io
