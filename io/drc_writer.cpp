#include "io/drc_writer.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <memory>

#include "draco/compression/encode.h"
#include "draco/mesh/mesh.h"
#include "draco/metadata/geometry_metadata.h"
#include "io/mesh_io.h"

namespace fq::io {

namespace {

/// Adds a per-point attribute with identity mapping and copies `values` into it.
template <typename T>
int add_point_attribute(draco::Mesh& dm, draco::GeometryAttribute::Type type, draco::DataType data_type,
                        int components, const T* values) {
  draco::GeometryAttribute ga;
  ga.Init(type, nullptr, components, data_type, false, sizeof(T) * components, 0);
  const int id = dm.AddAttribute(ga, true, dm.num_points());
  draco::PointAttribute* att = dm.attribute(id);
  for (uint32_t i = 0; i < dm.num_points(); ++i)
    att->SetAttributeValue(draco::AttributeValueIndex(i), values + size_t(i) * components);
  return id;
}

/// Vertex properties `names` (all present) as one Draco attribute of `type`: uint8 when they
/// all are uchar (colours as read), float32 otherwise. Their names go to `used`.
void add_properties(draco::Mesh& dm, const MeshAttributes& a, draco::GeometryAttribute::Type type,
                    const std::vector<const char*>& names, std::vector<std::string>& used) {
  std::vector<const ElementProperty*> props;
  props.reserve(names.size());
  for (const char* n : names) props.push_back(a.find_vertex(n));
  bool bytes = true;
  for (const ElementProperty* p : props) bytes = bytes && p->type == ScalarType::kUInt8;
  const size_t k = props.size(), n = dm.num_points();
  auto fill = [&](auto zero, draco::DataType data_type) {
    std::vector<decltype(zero)> values(n * k);
    for (size_t v = 0; v < n; ++v)
      for (size_t c = 0; c < k; ++c) values[v * k + c] = static_cast<decltype(zero)>(props[c]->values[v]);
    add_point_attribute(dm, type, data_type, int(k), values.data());
  };
  if (bytes)
    fill(uint8_t{}, draco::DT_UINT8);
  else
    fill(float{}, draco::DT_FLOAT32);
  for (const ElementProperty* p : props) used.push_back(p->name);
}

/// Normals, colours and texture coordinates of `a`, each when all its properties are there.
std::vector<std::string> add_attributes(draco::Mesh& dm, const MeshAttributes& a) {
  std::vector<std::string> used;
  auto all = [&](std::initializer_list<const char*> names) {
    for (const char* n : names)
      if (!a.find_vertex(n)) return false;
    return true;
  };
  if (all({"nx", "ny", "nz"}))
    add_properties(dm, a, draco::GeometryAttribute::NORMAL, {"nx", "ny", "nz"}, used);
  if (all({"red", "green", "blue", "alpha"}))
    add_properties(dm, a, draco::GeometryAttribute::COLOR, {"red", "green", "blue", "alpha"}, used);
  else if (all({"red", "green", "blue"}))
    add_properties(dm, a, draco::GeometryAttribute::COLOR, {"red", "green", "blue"}, used);
  if (const auto uv = a.vertex_uv(); uv[0])
    add_properties(dm, a, draco::GeometryAttribute::TEX_COORD, {uv[0]->name.c_str(), uv[1]->name.c_str()},
                   used);
  return used;
}

std::unique_ptr<draco::Mesh> to_draco(const MeshView& mesh, const uint32_t* labels, uint32_t num_clusters) {
  auto dm = std::make_unique<draco::Mesh>();
  dm->set_num_points(mesh.num_vertices);
  dm->SetNumFaces(mesh.num_triangles);
  for (uint32_t t = 0; t < mesh.num_triangles; ++t) {
    const uint32_t* tri = mesh.triangles + 3 * size_t(t);
    dm->SetFace(draco::FaceIndex(t),
                {draco::PointIndex(tri[0]), draco::PointIndex(tri[1]), draco::PointIndex(tri[2])});
  }
  add_point_attribute(*dm, draco::GeometryAttribute::POSITION, draco::DT_FLOAT32, 3, mesh.positions);
  if (labels) {
    const int id = add_point_attribute(*dm, draco::GeometryAttribute::GENERIC, draco::DT_UINT32, 1, labels);
    auto meta = std::make_unique<draco::AttributeMetadata>();
    meta->AddEntryString(kLabelMetadataKey, kLabelMetadataName);
    dm->AddAttributeMetadata(id, std::move(meta));
    dm->metadata()->AddEntryInt(kNumClustersMetadataKey, static_cast<int32_t>(num_clusters));
  }
  return dm;
}

}  // namespace

Status write_drc(const std::string& path, const MeshView& mesh, const uint32_t* labels, uint32_t num_clusters,
                 int position_bits, const MeshAttributes* attributes, std::vector<std::string>& dropped) {
  const std::unique_ptr<draco::Mesh> dm = to_draco(mesh, labels, num_clusters);
  if (attributes) {
    const std::vector<std::string> used = add_attributes(*dm, *attributes);
    std::vector<std::string> lost;
    for (const ElementProperty& p : attributes->vertex)
      if (std::find(used.begin(), used.end(), p.name) == used.end() && !(labels && is_label_property(p.name)))
        lost.push_back(p.name);  // (new labels replace those of an earlier run)
    for (const std::string& phrase : group_property_names(lost)) dropped.push_back("vertex " + phrase);
    for (const ElementProperty& p : attributes->face) dropped.push_back("face property '" + p.name + "'");
  }
  draco::Encoder encoder;
  // Generic integer attributes are never quantized by Draco, so labels stay exact.
  if (position_bits > 0) encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, position_bits);
  draco::EncoderBuffer buffer;
  const draco::Status s = encoder.EncodeMeshToBuffer(*dm, &buffer);
  if (!s.ok()) return invalid_input("cannot encode '" + path + "' with Draco: " + s.error_msg_string());
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  if (!f) return io_error("cannot open '" + path + "' for writing: " + std::strerror(errno));
  f.write(buffer.data(), std::streamsize(buffer.size()));
  f.close();
  if (!f) return io_error("cannot write '" + path + "': write failed (disk full?)");
  return {};
}

}  // namespace fq::io
