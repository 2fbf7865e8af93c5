#include "tests/daemon/draco_plain.h"

#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>
#include <gtest/gtest.h>

#include <string>
#include <type_traits>

namespace fq::test {
namespace {

void fill_points(const Mesh& m, draco::PointCloud& pc) {
  pc.set_num_points(m.num_vertices());
  draco::GeometryAttribute ga;
  ga.Init(draco::GeometryAttribute::POSITION, nullptr, 3, draco::DT_FLOAT32, false, sizeof(float) * 3, 0);
  const int id = pc.AddAttribute(ga, true, m.num_vertices());
  draco::PointAttribute* att = pc.attribute(id);
  for (uint32_t i = 0; i < m.num_vertices(); ++i)
    att->SetAttributeValue(draco::AttributeValueIndex(i), &m.positions[3 * size_t(i)]);
}

/// `geometry` (a mesh or a point cloud) in Draco's sequential encoding of its kind.
template <class Geometry>
std::string encode_sequential(const Geometry& geometry) {
  draco::Encoder enc;
  draco::EncoderBuffer buf;
  draco::Status s;
  if constexpr (std::is_same_v<Geometry, draco::Mesh>) {
    enc.SetEncodingMethod(draco::MESH_SEQUENTIAL_ENCODING);
    s = enc.EncodeMeshToBuffer(geometry, &buf);
  } else {
    enc.SetEncodingMethod(draco::POINT_CLOUD_SEQUENTIAL_ENCODING);
    s = enc.EncodePointCloudToBuffer(geometry, &buf);
  }
  EXPECT_TRUE(s.ok()) << s.error_msg_string();
  return std::string(buf.data(), buf.size());
}

}  // namespace

std::string draco_plain_mesh(const Mesh& m) {
  draco::Mesh mesh;
  fill_points(m, mesh);
  for (uint32_t f = 0; f < m.num_triangles(); ++f) {
    const uint32_t* t = &m.triangles[3 * size_t(f)];
    mesh.AddFace({draco::PointIndex(t[0]), draco::PointIndex(t[1]), draco::PointIndex(t[2])});
  }
  return encode_sequential(mesh);
}

std::string draco_point_cloud(const Mesh& m) {
  draco::PointCloud pc;
  fill_points(m, pc);
  return encode_sequential(pc);
}

}  // namespace fq::test
