#include "io/ply_reader.h"

#include <algorithm>
#include <initializer_list>
#include <optional>
#include <sstream>
#include <string_view>
#include <utility>
#include <vector>

#include "common/pair_table.h"
#include "draco/core/decoder_buffer.h"
#include "draco/io/ply_property_reader.h"
#include "draco/io/ply_reader.h"
#include "io/draco_reader.h"
#include "io/ply_extent_check.h"

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

/// The faces as triangles: a polygon of k corners becomes the fan of its k - 2 triangles
/// (0, i, i + 1), as Draco and assimp split OBJ polygons. `source` gets each triangle's face.
Status read_faces(const std::string& path, const draco::PlyElement* face, Mesh& out,
                  std::vector<uint32_t>& source) {
  if (!face || face->num_entries() == 0) return {};
  const draco::PlyProperty* idx = face->GetPropertyByName("vertex_indices");
  if (!idx) idx = face->GetPropertyByName("vertex_index");
  if (!idx || !idx->is_list()) return invalid_input("'" + path + "' has faces without vertex_indices");
  const draco::PlyPropertyReader<int64_t> reader(idx);
  const int n = face->num_entries();
  const int64_t num_vertices = out.num_vertices();
  out.triangles.reserve(3 * size_t(n));
  source.reserve(size_t(n));
  std::vector<uint32_t> corners;
  for (int f = 0; f < n; ++f) {
    const int64_t count = idx->GetListEntryNumValues(f);
    if (count < 3)
      return invalid_input("'" + path + "' is not a surface mesh: face " + std::to_string(f) + " has " +
                           std::to_string(count) + " vertices");
    const int64_t offset = idx->GetListEntryOffset(f);
    corners.clear();
    for (int64_t k = 0; k < count; ++k) {
      const int64_t v = reader.ReadValue(static_cast<int>(offset + k));
      if (v < 0 || v >= num_vertices)
        return invalid_input("cannot decode '" + path + "': face " + std::to_string(f) +
                             " references vertex " + std::to_string(v) + " of " +
                             std::to_string(num_vertices));
      corners.push_back(static_cast<uint32_t>(v));
    }
    for (size_t k = 1; k + 1 < corners.size(); ++k) {
      out.triangles.insert(out.triangles.end(), {corners[0], corners[k], corners[k + 1]});
      source.push_back(uint32_t(f));
    }
  }
  return {};
}

/// Face properties follow the faces into their triangles: each triangle of a polygon gets
/// the polygon's values.
void expand_to_triangles(std::vector<ElementProperty>& face, const std::vector<uint32_t>& source) {
  for (ElementProperty& p : face) {
    ElementProperty t = p;
    t.values.clear();
    t.offsets.clear();
    if (p.is_list) t.offsets.push_back(0);
    for (const uint32_t f : source) {
      if (!p.is_list) {
        t.values.push_back(p.values[f]);
        continue;
      }
      t.values.insert(t.values.end(), p.values.begin() + p.offsets[f], p.values.begin() + p.offsets[f + 1]);
      t.offsets.push_back(uint32_t(t.values.size()));
    }
    p = std::move(t);
  }
}

constexpr std::pair<draco::DataType, ScalarType> kScalarTypes[] = {
    {draco::DT_INT8, ScalarType::kInt8},       {draco::DT_UINT8, ScalarType::kUInt8},
    {draco::DT_INT16, ScalarType::kInt16},     {draco::DT_UINT16, ScalarType::kUInt16},
    {draco::DT_INT32, ScalarType::kInt32},     {draco::DT_UINT32, ScalarType::kUInt32},
    {draco::DT_FLOAT32, ScalarType::kFloat32}, {draco::DT_FLOAT64, ScalarType::kFloat64}};

/// False for the types PLY has no name for (64-bit integers).
bool scalar_type(draco::DataType t, ScalarType& out) {
  const std::optional<ScalarType> s = second_of(kScalarTypes, t);
  if (s) out = *s;
  return s.has_value();
}

/// Copies one property of `element`; false when its type has no PLY name we write.
bool copy_property(const draco::PlyElement& element, const draco::PlyProperty& p, ElementProperty& out) {
  out.name = p.name();
  out.is_list = p.is_list();
  if (!scalar_type(p.data_type(), out.type)) return false;
  if (out.is_list && !scalar_type(p.list_data_type(), out.count_type)) return false;
  const draco::PlyPropertyReader<double> reader(&p);
  const int n = element.num_entries();
  if (!out.is_list) {
    out.values.resize(size_t(n));
    for (int i = 0; i < n; ++i) out.values[size_t(i)] = reader.ReadValue(i);
    return true;
  }
  out.offsets.assign(1, 0);
  for (int i = 0; i < n; ++i) {
    const int64_t first = p.GetListEntryOffset(i), count = p.GetListEntryNumValues(i);
    for (int64_t k = 0; k < count; ++k) out.values.push_back(reader.ReadValue(static_cast<int>(first + k)));
    out.offsets.push_back(static_cast<uint32_t>(out.values.size()));
  }
  return true;
}

/// Every property of `element` but those in `skip`, into `out`; the others into `dropped`.
void keep_properties(const draco::PlyReader& reader, const std::string& name,
                     std::initializer_list<const char*> skip, std::vector<ElementProperty>& out,
                     std::vector<std::string>& dropped) {
  const draco::PlyElement* element = reader.GetElementByName(name);
  if (!element) return;
  for (int i = 0; i < element->num_properties(); ++i) {
    const draco::PlyProperty& p = element->property(i);
    if (std::find(skip.begin(), skip.end(), p.name()) != skip.end()) continue;
    ElementProperty kept;
    if (copy_property(*element, p, kept))
      out.push_back(std::move(kept));
    else
      dropped.push_back(name + " property '" + p.name() + "' (64-bit integer type)");
  }
}

/// Names of the header's elements (draco::PlyElement does not expose its name).
std::vector<std::string> element_names(const std::vector<char>& bytes) {
  std::vector<std::string> names;
  const std::string_view all(bytes.data(), bytes.size());
  std::istringstream header(std::string(all.substr(0, all.find("end_header"))));
  for (std::string line; std::getline(header, line);) {
    std::istringstream words(line);
    std::string key, name;
    if (words >> key >> name && key == "element") names.push_back(name);
  }
  return names;
}

void keep_attributes(const draco::PlyReader& reader, const std::vector<char>& bytes, MeshAttributes& a) {
  keep_properties(reader, "vertex", {"x", "y", "z"}, a.vertex, a.dropped);
  keep_properties(reader, "face", {"vertex_indices", "vertex_index"}, a.face, a.dropped);
  for (const std::string& name : element_names(bytes)) {
    if (name != "vertex" && name != "face") a.dropped.push_back("element '" + name + "'");
  }
}

}  // namespace

Status read_ply(const std::string& path, Mesh& out, MeshAttributes* attributes) {
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
  std::vector<uint32_t> source;  // each triangle's face
  const draco::PlyElement* face = reader.GetElementByName("face");
  Status st = read_vertices(path, reader.GetElementByName("vertex"), out);
  if (st.ok()) st = read_faces(path, face, out, source);
  if (st.ok() && attributes) {
    keep_attributes(reader, bytes, *attributes);
    if (face && source.size() != size_t(face->num_entries())) expand_to_triangles(attributes->face, source);
  }
  return st;
}

}  // namespace fq::io
