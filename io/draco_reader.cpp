#include "io/draco_reader.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <utility>

#include "common/pair_table.h"
#include "draco/compression/decode.h"
#include "draco/io/mesh_io.h"
#include "io/mesh_io.h"
#include "io/obj_corners.h"

namespace fq::io {

namespace {

/// What becomes an fq vertex: Draco's points (a point is one combination of attribute
/// values, so texture seams split a position into several points), or the distinct
/// position values (welded: one vertex per position, whatever the other attributes).
enum class Vertices { kPoints, kPositionValues };

/// Copies positions and faces out of a decoded Draco mesh.
Status from_draco(const std::string& path, const draco::Mesh& dm, Vertices vertices, Mesh& out) {
  const draco::PointAttribute* pos = dm.GetNamedAttribute(draco::GeometryAttribute::POSITION);
  if (!pos) return invalid_input("'" + path + "' has no vertex positions");
  if (pos->num_components() < 3)
    return invalid_input("'" + path + "' has " + std::to_string(pos->num_components()) +
                         "-D positions, not 3-D");
  const bool welded = vertices == Vertices::kPositionValues;
  const uint32_t n = welded ? uint32_t(pos->size()) : dm.num_points();
  auto value_of = [&](draco::PointIndex p) { return pos->mapped_index(p); };
  out.positions.resize(3 * size_t(n));
  for (uint32_t i = 0; i < n; ++i) {
    const draco::AttributeValueIndex v =
        welded ? draco::AttributeValueIndex(i) : value_of(draco::PointIndex(i));
    // ConvertValue reads any stored type (float, or integers in some files).
    if (!pos->ConvertValue<float>(v, 3, &out.positions[3 * size_t(i)]))
      return invalid_input("'" + path + "': cannot convert the position of vertex " + std::to_string(i));
  }
  out.triangles.resize(3 * size_t(dm.num_faces()));
  for (uint32_t f = 0; f < dm.num_faces(); ++f) {
    const draco::Mesh::Face& face = dm.face(draco::FaceIndex(f));
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = welded ? value_of(face[k]).value() : face[k].value();
      if (v >= n)
        return invalid_input("cannot decode '" + path + "': face " + std::to_string(f) +
                             " references vertex " + std::to_string(v) + " of " + std::to_string(n));
      out.triangles[3 * size_t(f) + k] = v;
    }
  }
  return {};
}

std::string draco_message(const draco::Status& s) {
  return s.error_msg_string().empty() ? std::string("unknown Draco error") : s.error_msg_string();
}

/// Binary STL: 80-byte header, uint32 count, 50 bytes per triangle. ASCII STL starts with
/// "solid" (a binary header may too, so the size test decides).
struct StlHead {
  bool says_solid = false;
  bool has_count = false;  ///< at least 84 bytes
  uint32_t count = 0;
  uint64_t size = 0;
  bool binary_size() const { return has_count && 84 + 50 * uint64_t(count) == size; }
};

StlHead stl_head(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  char head[84] = {};
  f.read(head, sizeof head);
  const auto got = f.gcount();
  StlHead h;
  std::error_code ec;
  h.size = std::filesystem::file_size(path, ec);
  h.says_solid = got >= 5 && std::memcmp(head, "solid", 5) == 0;
  h.has_count = got >= 84;
  for (int i = 0; i < 4 && h.has_count; ++i)
    h.count |= uint32_t(static_cast<unsigned char>(head[80 + i])) << (8 * i);
  return h;
}

Status check_stl_size(const std::string& path) {
  const StlHead h = stl_head(path);
  if (!h.has_count) return invalid_input("cannot decode '" + path + "': too short for an STL file");
  if (h.binary_size()) return {};
  return invalid_input("cannot decode '" + path + "': binary STL header announces " +
                       std::to_string(h.count) + " triangles but the file has " + std::to_string(h.size) +
                       " bytes");
}

/// The vertex properties a Draco attribute becomes (as fq's writers name them).
struct AttributeProperties {
  draco::GeometryAttribute::Type type;
  std::array<const char*, 4> names;  ///< per component; null past the last
};
constexpr AttributeProperties kKept[] = {{draco::GeometryAttribute::NORMAL, {"nx", "ny", "nz", nullptr}},
                                         {draco::GeometryAttribute::COLOR, {"red", "green", "blue", "alpha"}},
                                         {draco::GeometryAttribute::TEX_COORD, {"u", "v", nullptr, nullptr}}};

/// One vertex property per component of `att` (per point: read_drc's vertices are points);
/// uint8 values stay uchar (colours), others become float.
void keep_attribute(const draco::Mesh& dm, const draco::PointAttribute& att, const AttributeProperties& kept,
                    MeshAttributes& out) {
  const int k = std::min<int>(att.num_components(), 4);
  std::vector<float> value(size_t(att.num_components()));
  for (int c = 0; c < k && kept.names[c]; ++c) {
    ElementProperty p;
    p.name = kept.names[c];
    p.type = att.data_type() == draco::DT_UINT8 ? ScalarType::kUInt8 : ScalarType::kFloat32;
    p.values.resize(dm.num_points());
    out.vertex.push_back(std::move(p));
  }
  const size_t first = out.vertex.size() - std::min<size_t>(out.vertex.size(), size_t(k));
  for (uint32_t i = 0; i < dm.num_points(); ++i) {
    att.ConvertValue<float>(att.mapped_index(draco::PointIndex(i)), att.num_components(), value.data());
    for (size_t c = first; c < out.vertex.size(); ++c) out.vertex[c].values[i] = value[c - first];
  }
}

/// Normals, colours, texture coordinates and fq's labels of a .drc as vertex properties;
/// other attributes are named in `dropped`.
void keep_drc_attributes(const draco::Mesh& dm, MeshAttributes& out) {
  const int32_t label_id = [&] {
    const draco::AttributeMetadata* md =
        dm.GetAttributeMetadataByStringEntry(kLabelMetadataKey, kLabelMetadataName);
    return md ? int32_t(md->att_unique_id()) : -1;
  }();
  for (int i = 0; i < dm.num_attributes(); ++i) {
    const draco::PointAttribute& att = *dm.attribute(i);
    if (att.attribute_type() == draco::GeometryAttribute::POSITION) continue;
    if (int32_t(att.unique_id()) == label_id) {
      keep_attribute(dm, att, {draco::GeometryAttribute::GENERIC, {"label", nullptr, nullptr, nullptr}}, out);
      out.vertex.back().type = ScalarType::kUInt32;
      continue;
    }
    const AttributeProperties* kept = nullptr;
    for (const AttributeProperties& a : kKept)
      if (a.type == att.attribute_type()) kept = &a;
    if (kept && att.num_components() >= 2)
      keep_attribute(dm, att, *kept, out);
    else
      out.dropped.push_back("a " + std::string(att.TypeToString(att.attribute_type())) + " attribute");
  }
}

}  // namespace

Status read_file_bytes(const std::string& path, std::vector<char>& bytes) {
  std::ifstream f(path, std::ios::binary);
  if (!f) return io_error("cannot open '" + path + "' for reading");
  bytes.assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
  if (f.bad()) return io_error("cannot read '" + path + "': read error");
  return {};
}

bool is_ascii_stl(const std::string& path) {
  const StlHead h = stl_head(path);
  return h.says_solid && !h.binary_size();
}

Status read_drc(const std::string& path, Mesh& out, MeshAttributes* attributes) {
  std::vector<char> bytes;
  FQ_RETURN_IF_ERROR(read_file_bytes(path, bytes));
  draco::DecoderBuffer buffer;
  buffer.Init(bytes.data(), bytes.size());
  auto type = draco::Decoder::GetEncodedGeometryType(&buffer);
  if (!type.ok()) return invalid_input("cannot decode '" + path + "': " + draco_message(type.status()));
  if (type.value() != draco::TRIANGULAR_MESH)
    return invalid_input("'" + path + "' is not a triangle mesh (Draco point cloud)");
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
  if (!decoded.ok()) return invalid_input("cannot decode '" + path + "': " + draco_message(decoded.status()));
  if (attributes) keep_drc_attributes(*decoded.value(), *attributes);
  return from_draco(path, *decoded.value(), Vertices::kPoints, out);
}

Status read_obj_or_stl(const std::string& path, Mesh& out, MeshAttributes* attributes) {
  if (lower_extension(path) == ".stl") {
    FQ_RETURN_IF_ERROR(check_stl_size(path));
  }
  draco::Options options;
  options.SetBool("use_metadata", true);  // the OBJ's material names and library
  auto decoded = draco::ReadMeshFromFile(path, options);
  if (!decoded.ok()) return invalid_input("cannot decode '" + path + "': " + draco_message(decoded.status()));
  const std::unique_ptr<draco::Mesh> dm = std::move(decoded).value();
  if (!dm) return invalid_input("cannot decode '" + path + "': Draco returned no mesh");
  // STL facet normals follow from the triangles; an OBJ's normals, UVs and materials are
  // data, kept per triangle corner beside the welded vertices.
  if (attributes && lower_extension(path) == ".obj") keep_obj_corners(*dm, path, *attributes);
  // Welded: Draco splits a position into one point per texture coordinate or normal it
  // carries, which would cut the surface open along every seam.
  return from_draco(path, *dm, Vertices::kPositionValues, out);
}

}  // namespace fq::io
