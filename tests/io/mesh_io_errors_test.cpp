// fq_io on bad input: every failure is a one-line status naming the file, never a crash.
#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "draco/compression/encode.h"
#include "draco/point_cloud/point_cloud.h"
#include "io/mesh_io.h"
#include "tests/io/io_test_util.h"
#include "tests/support/test_meshes.h"

namespace fq::io {
namespace {

std::string garbage(size_t n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::string s(n, '\0');
  for (char& c : s) c = static_cast<char>(rng() & 0xff);
  return s;
}

void expect_read_error(const std::string& path, const std::string& needle) {
  Mesh m;
  m.positions = {1, 2, 3};
  const Status s = read_mesh(path, m);
  EXPECT_FALSE(s.ok()) << path;
  EXPECT_NE(s.message().find(needle), std::string::npos) << s.message();
  EXPECT_EQ(s.message().find('\n'), std::string::npos) << "one line: " << s.message();
  EXPECT_TRUE(m.positions.empty()) << "out is cleared on failure";
}

TEST(MeshIoErrors, MissingFile) { expect_read_error("/nonexistent/dir/mesh.ply", "no such file"); }

TEST(MeshIoErrors, FolderIsNotAFile) {
  test::ScratchDir dir;
  expect_read_error(dir.path().string(), "is a folder");
}

TEST(MeshIoErrors, UnsupportedExtension) {
  test::ScratchDir dir;
  test::write_bytes(dir.file("mesh.xyz"), "0 0 0\n");
  expect_read_error(dir.file("mesh.xyz"), "unsupported extension '.xyz'");
  test::write_bytes(dir.file("noext"), "ply\n");
  expect_read_error(dir.file("noext"), "unsupported extension");
}

TEST(MeshIoErrors, GarbageBytesInEveryFormat) {
  test::ScratchDir dir;
  uint32_t seed = 1;
  for (const char* name : {"g.ply", "g.drc", "g.obj", "g.stl"}) {
    for (size_t size : {size_t(0), size_t(7), size_t(5000)}) {
      const std::string path = dir.file(std::to_string(size) + name);
      test::write_bytes(path, garbage(size, seed++));
      Mesh m;
      const Status s = read_mesh(path, m);
      // Random bytes may happen to form a (meaningless) STL or OBJ; what matters is no crash,
      // no hang, and a clear message when it fails.
      if (!s.ok()) {
        EXPECT_NE(s.message().find(path), std::string::npos) << s.message();
        EXPECT_EQ(s.message().find('\n'), std::string::npos) << s.message();
      }
    }
  }
  expect_read_error(dir.file("5000g.ply"), "cannot decode");
  expect_read_error(dir.file("5000g.drc"), "cannot decode");
}

TEST(MeshIoErrors, BinaryStlWithLyingTriangleCount) {
  test::ScratchDir dir;
  std::string bytes(84, '\0');
  bytes[80] = '\xff';
  bytes[81] = '\xff';  // 65535 triangles announced, none present
  test::write_bytes(dir.file("short.stl"), bytes);
  expect_read_error(dir.file("short.stl"), "announces 65535 triangles");
}

TEST(MeshIoErrors, PlyHeaderAnnouncingTooMuch) {
  test::ScratchDir dir;
  test::write_bytes(dir.file("huge.ply"),
                    "ply\nformat ascii 1.0\nelement vertex 1000000000\nproperty float x\nproperty float y\n"
                    "property float z\nend_header\n0 0 0\n");
  expect_read_error(dir.file("huge.ply"), "cannot decode");
}

TEST(MeshIoErrors, TruncatedBinaryPly) {
  // Draco's PlyReader would read past the end of such a file; fq checks the extent first.
  test::ScratchDir dir;
  const Mesh mesh = test::make_icosphere(2, 1.0f);
  ASSERT_TRUE(write_mesh(dir.file("full.ply"), mesh.view(), nullptr, 0).ok());
  const std::string bytes = test::read_bytes(dir.file("full.ply"));
  const size_t body = bytes.find("end_header\n") + 11;
  const size_t vertex_bytes = 12 * size_t(mesh.num_vertices());
  for (size_t cut : {body + 5, body + vertex_bytes - 1, body + vertex_bytes + 7, bytes.size() - 1}) {
    const std::string path = dir.file("cut" + std::to_string(cut) + ".ply");
    test::write_bytes(path, bytes.substr(0, cut));
    expect_read_error(path, "truncated");
  }
  // A face whose list count runs past the end.
  std::string lying = bytes;
  lying[body + vertex_bytes + size_t{13} * (mesh.num_triangles() - 1)] = char(200);
  test::write_bytes(dir.file("lying.ply"), lying);
  expect_read_error(dir.file("lying.ply"), "truncated");
}

TEST(MeshIoErrors, BinaryPlyCountBeyondInt) {
  test::ScratchDir dir;
  test::write_bytes(dir.file("big.ply"),
                    "ply\nformat binary_little_endian 1.0\nelement vertex 3000000000\nproperty float x\n"
                    "property float y\nproperty float z\nend_header\n");
  expect_read_error(dir.file("big.ply"), "at most 2^31 - 1");
}

TEST(MeshIoErrors, BigEndianPlyIsNamed) {
  test::ScratchDir dir;
  test::write_bytes(
      dir.file("be.ply"),
      "ply\nformat binary_big_endian 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
      "property float z\nend_header\n");
  expect_read_error(dir.file("be.ply"), "binary_little_endian");
}

TEST(MeshIoErrors, PlyFaceOfTwoVerticesIsNotASurface) {
  test::ScratchDir dir;
  test::write_bytes(dir.file("edge.ply"),
                    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                    "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n"
                    "0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n2 0 3\n");
  expect_read_error(dir.file("edge.ply"), "face 1 has 2 vertices");
}

TEST(MeshIoErrors, PlyIndexOutOfRange) {
  test::ScratchDir dir;
  test::write_bytes(dir.file("bad.ply"),
                    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                    "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                    "0 0 0\n1 0 0\n1 1 0\n3 0 1 7\n");
  expect_read_error(dir.file("bad.ply"), "references vertex 7");
}

TEST(MeshIoErrors, DracoPointCloudIsNotATriangleMesh) {
  test::ScratchDir dir;
  draco::PointCloud pc;
  pc.set_num_points(3);
  draco::GeometryAttribute ga;
  ga.Init(draco::GeometryAttribute::POSITION, nullptr, 3, draco::DT_FLOAT32, false, 12, 0);
  const int id = pc.AddAttribute(ga, true, 3);
  const float p[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  for (int i = 0; i < 3; ++i)
    pc.attribute(id)->SetAttributeValue(draco::AttributeValueIndex(i), p + std::ptrdiff_t{3} * i);
  draco::Encoder encoder;
  draco::EncoderBuffer buffer;
  ASSERT_TRUE(encoder.EncodePointCloudToBuffer(pc, &buffer).ok());
  test::write_bytes(dir.file("pc.drc"), std::string(buffer.data(), buffer.size()));
  expect_read_error(dir.file("pc.drc"), "not a triangle mesh");
}

TEST(MeshIoErrors, WriteUnknownExtension) {
  test::ScratchDir dir;
  const Mesh m = test::make_single_triangle();
  const Status s = write_mesh(dir.file("out.stl"), m.view(), nullptr, 0);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.message().find("unsupported output extension '.stl'"), std::string::npos) << s.message();
}

TEST(MeshIoErrors, WriteUnwritablePath) {
  test::ScratchDir dir;
  const Mesh m = test::make_single_triangle();
  for (const std::string& path :
       {std::string("/nonexistent/dir/out.ply"), std::string("/nonexistent/dir/out.drc")}) {
    const Status s = write_mesh(path, m.view(), nullptr, 0);
    EXPECT_FALSE(s.ok()) << path;
    EXPECT_NE(s.message().find("cannot open"), std::string::npos) << s.message();
  }
  std::filesystem::create_directories(dir.file("taken.ply"));  // a folder where the file should go
  EXPECT_FALSE(write_mesh(dir.file("taken.ply"), m.view(), nullptr, 0).ok());
}

// Files that cannot be found, opened or written are i/o errors; bad content is invalid input.
TEST(MeshIoErrors, FileErrorsAreIoErrors) {
  test::ScratchDir dir;
  Mesh m;
  EXPECT_EQ(read_mesh("/nonexistent/dir/mesh.ply", m).code(), StatusCode::kIoError);
  EXPECT_EQ(read_mesh(dir.path().string(), m).code(), StatusCode::kIoError);
  const Mesh tri = test::make_single_triangle();
  EXPECT_EQ(write_mesh("/nonexistent/dir/out.ply", tri.view(), nullptr, 0).code(), StatusCode::kIoError);
  EXPECT_EQ(write_mesh("/nonexistent/dir/out.drc", tri.view(), nullptr, 0).code(), StatusCode::kIoError);
  test::write_bytes(dir.file("g.ply"), "ply\nnot a header");
  EXPECT_EQ(read_mesh(dir.file("g.ply"), m).code(), StatusCode::kInvalidInput);
}

TEST(MeshIoErrors, WriteRejectsBadLabelsIndicesAndBits) {
  test::ScratchDir dir;
  const Mesh m = test::make_single_triangle();
  const uint32_t labels[3] = {0, 1, 2};
  Status s = write_mesh(dir.file("l.ply"), m.view(), labels, 2);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.message().find("label 2"), std::string::npos) << s.message();

  Mesh broken = m;
  broken.triangles[2] = 9;
  EXPECT_FALSE(write_mesh(dir.file("b.ply"), broken.view(), nullptr, 0).ok());
  EXPECT_FALSE(write_mesh(dir.file("b.drc"), broken.view(), nullptr, 0).ok());

  s = write_mesh(dir.file("q.drc"), m.view(), nullptr, 0, 31);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.message().find("0..30"), std::string::npos) << s.message();
}

}  // namespace
}  // namespace fq::io
