// fq_io round trips: our PLY writer, Draco .drc with labels, and real meshes read
// with their vertex count and order intact.
#include "io/mesh_io.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <sstream>
#include <vector>

#include "draco/compression/decode.h"
#include "io/cluster_colors.h"
#include "tests/io/io_test_util.h"
#include "tests/support/mesh_dir.h"
#include "tests/support/test_meshes.h"

namespace fq::io {
namespace {

std::vector<uint32_t> labels_mod(uint32_t n, uint32_t k) {
  std::vector<uint32_t> l(n);
  for (uint32_t i = 0; i < n; ++i) l[i] = (i * 7 + 3) % k;
  return l;
}

uint32_t le32(const std::string& b, size_t at) {
  uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= uint32_t(static_cast<unsigned char>(b[at + i])) << (8 * i);
  return v;
}

TEST(MeshIoPly, RoundTripIsExactAndCarriesLabelsAndColours) {
  test::ScratchDir dir;
  const Mesh mesh = test::make_icosphere(2, 1.5f);
  const std::vector<uint32_t> labels = labels_mod(mesh.num_vertices(), 5);
  const std::string path = dir.file("sphere.ply");
  ASSERT_TRUE(write_mesh(path, mesh.view(), labels.data(), 5).ok());

  Mesh back;
  const Status s = read_mesh(path, back);
  ASSERT_TRUE(s.ok()) << s.message();
  EXPECT_EQ(back.positions, mesh.positions);
  EXPECT_EQ(back.triangles, mesh.triangles);

  const std::string bytes = test::read_bytes(path);
  const size_t end = bytes.find("end_header\n");
  ASSERT_NE(end, std::string::npos);
  const std::string header = bytes.substr(0, end);
  EXPECT_NE(header.find("format binary_little_endian 1.0"), std::string::npos);
  EXPECT_NE(
      header.find("property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uint label\n"
                  "property uchar cluster_red\nproperty uchar cluster_green\nproperty uchar cluster_blue\n"),
      std::string::npos);
  EXPECT_NE(header.find("property list uchar int vertex_indices"), std::string::npos);
  // Vertex records: 3 floats, 3 colour bytes (the input had none: the cluster colours),
  // uint label, 3 cluster colour bytes.
  const size_t body = end + std::strlen("end_header\n");
  ASSERT_EQ(bytes.size(), body + 22 * size_t(mesh.num_vertices()) + 13 * size_t(mesh.num_triangles()));
  for (uint32_t v = 0; v < mesh.num_vertices(); ++v) {
    const size_t at = body + 22 * size_t(v);
    ASSERT_EQ(le32(bytes, at + 15), labels[v]) << v;
    const Rgb8 c = cluster_color(labels[v]);
    for (const size_t rgb : {at + 12, at + 19}) {
      ASSERT_EQ(uint8_t(bytes[rgb]), c.r);
      ASSERT_EQ(uint8_t(bytes[rgb + 1]), c.g);
      ASSERT_EQ(uint8_t(bytes[rgb + 2]), c.b);
    }
  }
}

TEST(MeshIoPly, WithoutLabelsOnlyPositions) {
  test::ScratchDir dir;
  const Mesh mesh = test::make_cube(2, 1.0f);
  const std::string path = dir.file("cube.PLY");  // extensions are case-insensitive
  ASSERT_TRUE(write_mesh(path, mesh.view(), nullptr, 0).ok());
  const std::string bytes = test::read_bytes(path);
  EXPECT_EQ(bytes.find("label"), std::string::npos);
  EXPECT_EQ(bytes.find("red"), std::string::npos);
  Mesh back;
  ASSERT_TRUE(read_mesh(path, back).ok());
  EXPECT_EQ(back.positions, mesh.positions);
}

TEST(MeshIoPly, ZeroFacesReadsFine) {
  test::ScratchDir dir;
  Mesh points;
  points.positions = {0, 0, 0, 1, 2, 3};
  const std::string path = dir.file("points.ply");
  ASSERT_TRUE(write_mesh(path, points.view(), nullptr, 0).ok());
  Mesh back;
  ASSERT_TRUE(read_mesh(path, back).ok());
  EXPECT_EQ(back.num_vertices(), 2u);
  EXPECT_EQ(back.num_triangles(), 0u);
}

TEST(MeshIoPly, ReadsAsciiPly) {
  test::ScratchDir dir;
  const std::string path = dir.file("ascii.ply");
  test::write_bytes(path,
                    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                    "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n"
                    "0 0 0\n1 0 0\n1 1 0\n0 1 0.5\n3 0 1 2\n3 0 2 3\n");
  Mesh m;
  ASSERT_TRUE(read_mesh(path, m).ok());
  EXPECT_EQ(m.positions, (std::vector<float>{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0.5f}));
  EXPECT_EQ(m.triangles, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
}

TEST(MeshIoPly, CoincidentVerticesStaySeparate) {
  // Draco's own PLY decoder would merge these; fq must keep the file's vertices.
  test::ScratchDir dir;
  const Mesh soup = test::make_triangle_soup(test::make_cube(2, 1.0f));
  const std::string path = dir.file("soup.ply");
  ASSERT_TRUE(write_mesh(path, soup.view(), nullptr, 0).ok());
  Mesh back;
  ASSERT_TRUE(read_mesh(path, back).ok());
  EXPECT_EQ(back.num_vertices(), soup.num_vertices());
  EXPECT_EQ(back.positions, soup.positions);
  EXPECT_EQ(back.triangles, soup.triangles);
}

TEST(MeshIoPly, PolygonsAreSplitIntoTrianglesWithTheirFaceProperties) {
  test::ScratchDir dir;
  test::write_bytes(dir.file("quads.ply"),
                    "ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\nproperty float y\n"
                    "property float z\nelement face 3\nproperty list uchar int vertex_indices\n"
                    "property uchar red\nend_header\n"
                    "0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 0 0\n2 1 0\n4 0 1 2 3 10\n4 1 4 5 2 20\n3 0 2 3 30\n");
  Mesh mesh;
  MeshAttributes a;
  const Status s = read_mesh(dir.file("quads.ply"), mesh, &a);
  ASSERT_TRUE(s.ok()) << s.message();
  EXPECT_EQ(mesh.triangles, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3, 1, 4, 5, 1, 5, 2, 0, 2, 3}));
  ASSERT_EQ(a.face.size(), 1u);
  EXPECT_EQ(a.face[0].values, (std::vector<double>{10, 10, 20, 20, 30}));  // each triangle its face's
}

TEST(MeshIoObjStl, ObjTextureSeamsAreWeldedInFileOrder) {
  // Every corner has its own texture coordinate: Draco makes one point per corner; fq
  // must still see one vertex per `v` line, in file order, with the file's faces.
  test::ScratchDir dir;
  const Mesh mesh = test::make_icosphere(1, 1.0f);
  std::ostringstream obj;  // (not "literal" + std::string: GCC 12 warns falsely)
  obj.precision(9);
  for (uint32_t v = 0; v < mesh.num_vertices(); ++v) {
    const Vec3 p = test::vertex(mesh, v);
    obj << "v " << p.x << " " << p.y << " " << p.z << "\n";
  }
  for (uint32_t c = 0; c < 3 * mesh.num_triangles(); ++c) obj << "vt " << c * 1e-3 << " 0.5\n";
  for (uint32_t t = 0; t < mesh.num_triangles(); ++t) {
    obj << "f";
    for (int k = 0; k < 3; ++k) obj << " " << mesh.triangles[3 * t + k] + 1 << "/" << 3 * t + k + 1;
    obj << "\n";
  }
  test::write_bytes(dir.file("seams.obj"), obj.str());
  Mesh back;
  const Status s = read_mesh(dir.file("seams.obj"), back);
  ASSERT_TRUE(s.ok()) << s.message();
  ASSERT_EQ(back.num_vertices(), mesh.num_vertices());
  EXPECT_EQ(back.triangles, mesh.triangles);
  for (uint32_t i = 0; i < 3 * mesh.num_vertices(); ++i)
    EXPECT_NEAR(back.positions[i], mesh.positions[i], 1e-6);
}

TEST(MeshIoObjStl, BinaryStlIsWelded) {
  // STL stores three corners per facet; welding gives back the shared vertices.
  test::ScratchDir dir;
  const Mesh mesh = test::make_cube(2, 1.0f);
  std::string stl(80, '\0');
  auto put = [&stl](const void* p, size_t n) { stl.append(static_cast<const char*>(p), n); };
  const uint32_t count = mesh.num_triangles();
  put(&count, 4);
  for (uint32_t t = 0; t < count; ++t) {
    const float normal[3] = {0, 0, 0};
    put(normal, 12);
    for (int k = 0; k < 3; ++k) put(&mesh.positions[3 * mesh.triangles[3 * t + k]], 12);
    put("\0\0", 2);
  }
  test::write_bytes(dir.file("cube.stl"), stl);
  Mesh back;
  const Status s = read_mesh(dir.file("cube.stl"), back);
  ASSERT_TRUE(s.ok()) << s.message();
  EXPECT_EQ(back.num_vertices(), mesh.num_vertices());
  EXPECT_EQ(back.num_triangles(), mesh.num_triangles());
}

/// Index of the original vertex nearest to p (brute force; small meshes only).
uint32_t nearest(const Mesh& m, const float* p, double& dist) {
  dist = INFINITY;
  uint32_t best = 0;
  for (uint32_t v = 0; v < m.num_vertices(); ++v) {
    double d2 = 0;
    for (int k = 0; k < 3; ++k) d2 += std::pow(double(m.positions[3 * v + k]) - p[k], 2);
    if (d2 < dist) {
      dist = d2;
      best = v;
    }
  }
  dist = std::sqrt(dist);
  return best;
}

TEST(MeshIoDrc, RoundTripWithinQuantizationAndLabelsAttribute) {
  test::ScratchDir dir;
  const Mesh mesh = test::make_icosphere(3, 2.0f);
  const std::vector<uint32_t> labels = labels_mod(mesh.num_vertices(), 9);
  const std::string path = dir.file("sphere.drc");
  const int bits = 12;
  ASSERT_TRUE(write_mesh(path, mesh.view(), labels.data(), 9, bits).ok());

  Mesh back;
  ASSERT_TRUE(read_mesh(path, back).ok());
  EXPECT_EQ(back.num_vertices(), mesh.num_vertices());
  EXPECT_EQ(back.num_triangles(), mesh.num_triangles());
  // Draco quantizes over the largest bbox extent (4 here) into 2^bits - 1 steps.
  const double step = 4.0 / ((1 << bits) - 1);

  // Decode with Draco itself and find the labels by their metadata name.
  const std::string bytes = test::read_bytes(path);
  draco::DecoderBuffer buffer;
  buffer.Init(bytes.data(), bytes.size());
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
  ASSERT_TRUE(decoded.ok());
  const draco::Mesh& dm = *decoded.value();
  const int id = dm.GetAttributeIdByMetadataEntry(kLabelMetadataKey, kLabelMetadataName);
  ASSERT_GE(id, 0) << "no attribute named fq_label";
  const draco::PointAttribute* att = dm.attribute(id);
  EXPECT_EQ(att->attribute_type(), draco::GeometryAttribute::GENERIC);
  EXPECT_EQ(att->data_type(), draco::DT_UINT32);
  int32_t clusters = 0;
  ASSERT_TRUE(dm.GetMetadata()->GetEntryInt(kNumClustersMetadataKey, &clusters));
  EXPECT_EQ(clusters, 9);

  // Draco may reorder points: match each decoded point to its original by position.
  const draco::PointAttribute* pos = dm.GetNamedAttribute(draco::GeometryAttribute::POSITION);
  for (uint32_t p = 0; p < dm.num_points(); ++p) {
    float xyz[3];
    uint32_t label = 0;
    pos->ConvertValue<float>(pos->mapped_index(draco::PointIndex(p)), 3, xyz);
    att->GetMappedValue(draco::PointIndex(p), &label);
    double dist = 0;
    const uint32_t v = nearest(mesh, xyz, dist);
    ASSERT_LE(dist, std::sqrt(3.0) * step / 2 + 1e-6) << p;
    ASSERT_EQ(label, labels[v]) << p;
  }
}

TEST(MeshIoDrc, LosslessWhenBitsAreZero) {
  test::ScratchDir dir;
  const Mesh mesh = test::make_cube(2, 1.0f);
  const std::string path = dir.file("cube.drc");
  ASSERT_TRUE(write_mesh(path, mesh.view(), nullptr, 0, 0).ok());
  Mesh back;
  ASSERT_TRUE(read_mesh(path, back).ok());
  for (uint32_t p = 0; p < back.num_vertices(); ++p) {
    double dist = 0;
    nearest(mesh, &back.positions[3 * p], dist);
    EXPECT_EQ(dist, 0.0) << p;
  }
}

TEST(MeshIoReal, PlyKeepsVertexCountsOfSharedMeshes) {
  struct Case {
    const char* file;
    uint32_t v, f;
  };
  // dragon.ply has 51,986 coincident vertices that a deduplicating reader would merge.
  for (const Case& c : {Case{"bunny.ply", 34834, 69451}, Case{"dragon.ply", 435545, 871306}}) {
    const auto path = test::find_mesh(c.file);
    if (!path) GTEST_SKIP() << c.file << " not found in " << test::mesh_dir();
    Mesh m;
    const Status s = read_mesh(*path, m);
    ASSERT_TRUE(s.ok()) << s.message();
    EXPECT_EQ(m.num_vertices(), c.v) << c.file;
    EXPECT_EQ(m.num_triangles(), c.f) << c.file;
  }
}

TEST(MeshIoReal, BunnyFirstVertexIsTheFilesFirstVertex) {
  const auto path = test::find_mesh("bunny.ply");
  if (!path) GTEST_SKIP() << "bunny.ply not found in " << test::mesh_dir();
  Mesh m;
  ASSERT_TRUE(read_mesh(*path, m).ok());
  // Binary PLY, float x y z first: the first 12 bytes after the header.
  const std::string bytes = test::read_bytes(*path);
  const size_t body = bytes.find("end_header\n") + std::strlen("end_header\n");
  float first[3];
  std::memcpy(first, bytes.data() + body, sizeof first);
  EXPECT_EQ(m.positions[0], first[0]);
  EXPECT_EQ(m.positions[1], first[1]);
  EXPECT_EQ(m.positions[2], first[2]);
}

TEST(ClusterColors, DeterministicAndWellSeparated) {
  for (uint32_t k = 0; k < 100; ++k) {
    const Rgb8 a = cluster_color(k), b = cluster_color(k);
    EXPECT_TRUE(a.r == b.r && a.g == b.g && a.b == b.b);
  }
  for (uint32_t a = 0; a < 16; ++a) {
    for (uint32_t b = a + 1; b < 16; ++b) {
      const Rgb8 x = cluster_color(a), y = cluster_color(b);
      const double d = std::sqrt(std::pow(x.r - y.r, 2) + std::pow(x.g - y.g, 2) + std::pow(x.b - y.b, 2));
      EXPECT_GT(d, 40.0) << a << " vs " << b;
    }
  }
}

}  // namespace
}  // namespace fq::io
