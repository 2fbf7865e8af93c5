// fqfilter keeps what it does not change: a PLY's colours, normals (recomputed), texture
// coordinates, scalars and face properties; refuses to overwrite its input; reads ASCII
// STL; shows progress only on a terminal. Outputs are read back with Draco's PLY parser.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "draco/compression/decode.h"
#include "draco/core/decoder_buffer.h"
#include "draco/io/ply_property_reader.h"
#include "draco/io/ply_reader.h"
#include "io/mesh_io.h"
#include "tests/io/fqfilter_run.h"
#include "tests/io/io_test_util.h"

namespace {

namespace fs = std::filesystem;
using fq::test::run_fqfilter;
using fq::test::RunResult;
using fq::test::ScratchDir;

constexpr int kN = 8;  // grid of kN x kN vertices
const std::string kFandisk = std::string(FQ_DATA_DIR) + "/fandisk.ply";

/// An ASCII PLY of a bumpy grid with (deliberately wrong) normals, colours, UVs, a scalar,
/// face colours, per-face texture coordinate lists and an element fq cannot keep.
std::string attributed_ply() {
  std::ostringstream s;
  const int faces = 2 * (kN - 1) * (kN - 1);
  s << "ply\nformat ascii 1.0\nelement vertex " << kN * kN
    << "\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\n"
       "property float nz\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nproperty float u\n"
       "property float v\nproperty float quality\nelement face "
    << faces
    << "\nproperty list uchar int vertex_indices\nproperty uchar red\nproperty list uchar float texcoord\n"
       "element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n";
  for (int i = 0; i < kN; ++i) {
    for (int j = 0; j < kN; ++j) {
      s << i << " " << j << " " << 0.05 * std::sin(i) * std::cos(j) << " 1 0 0 " << i * 30 << " " << j * 30
        << " 7 " << i / double(kN - 1) << " " << j / double(kN - 1) << " " << i * kN + j << "\n";
    }
  }
  int f = 0;
  for (int i = 0; i + 1 < kN; ++i) {
    for (int j = 0; j + 1 < kN; ++j) {
      const int a = i * kN + j, b = a + kN, c = b + 1, d = a + 1;
      s << "3 " << a << " " << b << " " << c << " " << f++ % 256 << " 6 0 0 1 0 1 1\n";
      s << "3 " << a << " " << c << " " << d << " " << f++ % 256 << " 6 0 0 1 1 0 1\n";
    }
  }
  s << "0 1\n";
  return s.str();
}

/// A PLY file parsed by Draco's reader, with its values by element and property name.
class PlyFile {
 public:
  explicit PlyFile(const std::string& path) : bytes_(fq::test::read_bytes(path)) {
    buffer_.Init(bytes_.data(), bytes_.size());
    ok_ = reader_.Read(&buffer_).ok();
  }
  bool ok() const { return ok_; }
  bool has(const char* element, const char* property) const {
    const draco::PlyElement* e = reader_.GetElementByName(element);
    return e && e->GetPropertyByName(property);
  }
  /// Scalar values, or every list item in order.
  std::vector<double> values(const char* element, const char* property) const {
    const draco::PlyElement* e = reader_.GetElementByName(element);
    const draco::PlyProperty* p = e ? e->GetPropertyByName(property) : nullptr;
    if (!p) return {};
    const draco::PlyPropertyReader<double> r(p);
    std::vector<double> out;
    const int n = p->is_list() ? static_cast<int>(p->GetListEntryOffset(e->num_entries() - 1) +
                                                  p->GetListEntryNumValues(e->num_entries() - 1))
                               : e->num_entries();
    for (int i = 0; i < n; ++i) out.push_back(r.ReadValue(i));
    return out;
  }

 private:
  std::string bytes_;
  draco::DecoderBuffer buffer_;
  draco::PlyReader reader_;
  bool ok_ = false;
};

struct KeepFixture : ::testing::Test {
  ScratchDir dir;
  std::string in = dir.file("in.ply");
  void SetUp() override { fq::test::write_bytes(in, attributed_ply()); }
};

TEST_F(KeepFixture, PlyKeepsColoursUvsScalarsAndFaceProperties) {
  const std::string out = dir.file("out.ply");
  const RunResult r = run_fqfilter({in, out, "--cluster", "--threads", "2"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const PlyFile a(in), b(out);
  ASSERT_TRUE(a.ok() && b.ok());
  for (const char* p : {"red", "green", "blue", "u", "v", "quality"})
    EXPECT_EQ(b.values("vertex", p), a.values("vertex", p)) << p;
  for (const char* p : {"red", "texcoord"}) EXPECT_EQ(b.values("face", p), a.values("face", p)) << p;
  EXPECT_NE(b.values("vertex", "x"), a.values("vertex", "x"));  // it did filter
  EXPECT_TRUE(b.has("vertex", "label") && b.has("vertex", "cluster_red"));
  EXPECT_NE(r.err.find("element 'edge'"), std::string::npos) << r.err;  // named in a warning
}

TEST_F(KeepFixture, NormalsFollowTheFilteredSurface) {
  const std::string out = dir.file("out.ply");
  ASSERT_EQ(run_fqfilter({in, out, "--threads", "2"}, dir).exit_code, 0);
  const PlyFile b(out);
  const auto nx = b.values("vertex", "nx"), ny = b.values("vertex", "ny"), nz = b.values("vertex", "nz");
  ASSERT_EQ(nz.size(), size_t(kN * kN));
  for (size_t v = 0; v < nz.size(); ++v) {
    // The input said (1, 0, 0); the surface is a gently bumped z = 0 plane.
    EXPECT_NEAR(nx[v] * nx[v] + ny[v] * ny[v] + nz[v] * nz[v], 1.0, 1e-4) << v;
    EXPECT_GT(std::abs(nz[v]), 0.9) << v;
  }
}

TEST_F(KeepFixture, ColourClustersReplacesTheColours) {
  const std::string out = dir.file("out.ply");
  ASSERT_EQ(run_fqfilter({in, out, "--no-filter", "--colour-clusters", "--theta", "0.5"}, dir).exit_code, 0);
  const PlyFile b(out);
  EXPECT_EQ(b.values("vertex", "red"), b.values("vertex", "cluster_red"));
  EXPECT_EQ(b.values("vertex", "blue"), b.values("vertex", "cluster_blue"));
  EXPECT_NE(b.values("vertex", "red"), PlyFile(in).values("vertex", "red"));
}

TEST_F(KeepFixture, DrcKeepsNormalsColoursAndUvsAndWarnsOnceAGroup) {
  const RunResult r = run_fqfilter({in, dir.file("out.drc"), "--json", "--drc-bits", "0"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  std::string all;
  for (const auto& w : j["warnings"]) all += w.get<std::string>() + "\n";
  for (const char* p :
       {"vertex property 'quality'", "face property 'red'", "face property 'texcoord'", "element 'edge'"})
    EXPECT_NE(all.find(p), std::string::npos) << p << " in " << all;
  EXPECT_EQ(j["warnings"].size(), 4u) << all;  // nothing about normals, colours or uvs
  // Read back by Draco's decoder: the attributes are Draco's own, with the values fq wrote.
  const std::string bytes = fq::test::read_bytes(dir.file("out.drc"));
  draco::DecoderBuffer buffer;
  buffer.Init(bytes.data(), bytes.size());
  auto decoded = draco::Decoder().DecodeMeshFromBuffer(&buffer);
  ASSERT_TRUE(decoded.ok());
  const draco::Mesh& dm = *decoded.value();
  const draco::PointAttribute* colour = dm.GetNamedAttribute(draco::GeometryAttribute::COLOR);
  const draco::PointAttribute* normal = dm.GetNamedAttribute(draco::GeometryAttribute::NORMAL);
  const draco::PointAttribute* uv = dm.GetNamedAttribute(draco::GeometryAttribute::TEX_COORD);
  ASSERT_TRUE(colour && normal && uv);
  EXPECT_EQ(colour->data_type(), draco::DT_UINT8);
  const PlyFile a(in);
  const auto red = a.values("vertex", "red"), u = a.values("vertex", "u");
  const draco::PointAttribute* position = dm.GetNamedAttribute(draco::GeometryAttribute::POSITION);
  const auto x = a.values("vertex", "x"), y = a.values("vertex", "y");
  for (uint32_t p = 0; p < dm.num_points(); ++p) {
    // Draco may reorder points: find the input vertex by its grid position (x, y stay near
    // their integer grid values under the filter).
    float xyz[3], n[3], t[2];
    uint8_t rgb[3];
    position->ConvertValue<float>(position->mapped_index(draco::PointIndex(p)), 3, xyz);
    const size_t v = size_t(std::lround(xyz[0])) * kN + size_t(std::lround(xyz[1]));
    colour->ConvertValue<uint8_t>(colour->mapped_index(draco::PointIndex(p)), 3, rgb);
    normal->ConvertValue<float>(normal->mapped_index(draco::PointIndex(p)), 3, n);
    uv->ConvertValue<float>(uv->mapped_index(draco::PointIndex(p)), 2, t);
    EXPECT_EQ(rgb[0], red[v]);
    EXPECT_FLOAT_EQ(t[0], float(u[v]));
    EXPECT_GT(std::abs(n[2]), 0.9f);  // recomputed from the filtered surface, as for PLY
  }
}

TEST_F(KeepFixture, PlyQuadsFilter) {
  // The grid as quads: fqfilter splits each in two triangles, filters, writes triangles.
  std::ostringstream s;
  s << "ply\nformat ascii 1.0\nelement vertex " << kN * kN
    << "\nproperty float x\nproperty float y\nproperty float z\nelement face " << (kN - 1) * (kN - 1)
    << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (int i = 0; i < kN; ++i)
    for (int j = 0; j < kN; ++j) s << i << " " << j << " " << 0.05 * std::sin(3 * i + j) << "\n";
  for (int i = 0; i + 1 < kN; ++i)
    for (int j = 0; j + 1 < kN; ++j)
      s << "4 " << i * kN + j << " " << (i + 1) * kN + j << " " << (i + 1) * kN + j + 1 << " "
        << i * kN + j + 1 << "\n";
  fq::test::write_bytes(dir.file("quads.ply"), s.str());
  const RunResult r = run_fqfilter({dir.file("quads.ply"), dir.file("out.ply"), "--threads", "2"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const PlyFile b(dir.file("out.ply"));
  ASSERT_TRUE(b.ok());
  EXPECT_EQ(b.values("face", "vertex_indices").size(), size_t(3 * 2 * (kN - 1) * (kN - 1)));
  EXPECT_NE(b.values("vertex", "z"), PlyFile(dir.file("quads.ply")).values("vertex", "z"));  // it did filter
}

TEST_F(KeepFixture, RefusesToWriteOverTheInput) {
  const std::string before = fq::test::read_bytes(in);
  fs::create_symlink(in, dir.file("link.ply"));
  fs::create_hard_link(in, dir.file("hard.ply"));
  for (const std::string& out : {in, dir.file("link.ply"), dir.file("hard.ply"), dir.file("./in.ply")}) {
    const RunResult r = run_fqfilter({in, out}, dir);
    EXPECT_EQ(r.exit_code, 2) << out;
    EXPECT_NE(r.err.find("--in-place"), std::string::npos) << r.err;
  }
  EXPECT_EQ(fq::test::read_bytes(in), before);
}

TEST_F(KeepFixture, InPlaceReplacesTheInputThroughALink) {
  fs::create_symlink(in, dir.file("link.ply"));
  const std::vector<double> x_before = PlyFile(in).values("vertex", "x");
  const RunResult r = run_fqfilter({dir.file("link.ply"), dir.file("link.ply"), "--in-place"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::is_symlink(dir.file("link.ply")));
  const PlyFile b(in);  // the link's target holds the result, properties and all
  ASSERT_TRUE(b.ok());
  EXPECT_NE(b.values("vertex", "x"), x_before);
  EXPECT_TRUE(b.has("vertex", "quality"));
  for (const auto& e : fs::directory_iterator(dir.path()))
    EXPECT_EQ(e.path().string().find("fq-tmp"), std::string::npos);  // no temporary left
}

TEST(FqfilterFormats, ReadsAsciiStl) {
  ScratchDir dir;
  const std::string stl = dir.file("square.stl");
  fq::test::write_bytes(
      stl,
      "solid square\n"
      " facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 1 1 0\n"
      "  endloop\n endfacet\n"
      " facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 1 0\n   vertex 0 1 0\n"
      "  endloop\n endfacet\nendsolid square\n");
  fq::Mesh mesh;
  ASSERT_TRUE(fq::io::read_mesh(stl, mesh).ok());
  EXPECT_EQ(mesh.num_vertices(), 4u);  // welded: the shared edge's corners are one vertex each
  EXPECT_EQ(mesh.num_triangles(), 2u);
  EXPECT_EQ(mesh.triangles[3], mesh.triangles[0]);
  const RunResult r = run_fqfilter({stl, "--json", "--no-filter"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["vertices"], 4);
}

TEST(FqfilterProgress, OnlyOnATerminal) {
  ScratchDir dir;
  const RunResult piped = run_fqfilter({kFandisk, "--threads", "2"}, dir);
  ASSERT_EQ(piped.exit_code, 0);
  EXPECT_EQ(piped.err.find("done ("), std::string::npos) << piped.err;
  if (std::system("command -v script >/dev/null 2>&1") != 0) GTEST_SKIP() << "no script(1) for a terminal";
  // script(1) gives fqfilter a pseudo-terminal; what it wrote there lands in tty.txt.
  for (const bool json : {false, true}) {
    const std::string cmd = "script -qec " +
                            fq::test::quote(fq::test::quote(FQFILTER_BIN) + " " + fq::test::quote(kFandisk) +
                                            " --threads 2" + (json ? " --json" : "") + " >/dev/null") +
                            " /dev/null >" + fq::test::quote(dir.file("tty.txt"));
    ASSERT_EQ(fq::test::exit_code_of(std::system(cmd.c_str())), 0);
    const std::string tty = fq::test::read_bytes(dir.file("tty.txt"));
    EXPECT_EQ(tty.find("refine done (") != std::string::npos, !json) << tty;
  }
}

}  // namespace
