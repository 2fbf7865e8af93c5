#include "io/drc_writer.h"

#include <cerrno>
#include <cstring>
#include <fstream>
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
                 int position_bits) {
  const std::unique_ptr<draco::Mesh> dm = to_draco(mesh, labels, num_clusters);
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
