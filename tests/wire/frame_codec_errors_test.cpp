// Frames the codec must refuse, and plain Draco meshes from other producers.
#include <draco/compression/encode.h>
#include <draco/core/draco_types.h>
#include <draco/mesh/mesh.h>
#include <draco/metadata/geometry_metadata.h>
#include <draco/point_cloud/point_cloud.h>
#include <gtest/gtest.h>

#include <limits>
#include <map>
#include <memory>
#include <string>

#include "tests/wire/wire_test_meshes.h"
#include "wire/frame_codec.h"

namespace fq::wire {
namespace {

using test_wire::triangle_set;

std::vector<std::string> encode(const Mesh& m, uint32_t chunks) {
  std::vector<std::string> out;
  const Status s = encode_frame(m.view(), nullptr, chunks, CodecOptions{}, out);
  EXPECT_TRUE(s.ok()) << s.message();
  return out;
}

Status decode(const std::vector<std::string>& chunks, uint32_t vertex_count, Mesh& out) {
  std::vector<std::string_view> v(chunks.begin(), chunks.end());
  CodecOptions o;
  o.threads = 2;
  return decode_frame(v, vertex_count, o, out, nullptr);
}

/// `m` as a plain Draco mesh (no fq attributes, float positions kept exactly), as any
/// producer using draco::Encoder would send it. With `cloud`, a point cloud instead. With
/// `vid`, also an "fq_vid" attribute of type `vid_type` holding vid[v] for vertex v.
/// Points (float positions, kept exactly) and faces of `m`, one point per vertex, into `dm`.
void fill_draco_mesh(const Mesh& m, draco::Mesh& dm) {
  dm.set_num_points(m.num_vertices());
  draco::GeometryAttribute ga;
  ga.Init(draco::GeometryAttribute::POSITION, nullptr, 3, draco::DT_FLOAT32, false, 12, 0);
  auto* pa = dm.attribute(dm.AddAttribute(ga, true, m.num_vertices()));
  for (uint32_t v = 0; v < m.num_vertices(); ++v)
    pa->SetAttributeValue(draco::AttributeValueIndex(v), &m.positions[3 * v]);
  for (uint32_t t = 0; t < m.num_triangles(); ++t) {
    dm.AddFace({draco::PointIndex(m.triangles[3 * t]), draco::PointIndex(m.triangles[3 * t + 1]),
                draco::PointIndex(m.triangles[3 * t + 2])});
  }
}

std::string plain_draco(const Mesh& m, bool cloud = false, const std::vector<uint32_t>* vid = nullptr,
                        draco::DataType vid_type = draco::DT_UINT32) {
  draco::Mesh dm;
  fill_draco_mesh(m, dm);
  draco::GeometryAttribute ga;
  if (vid) {
    ga.Init(draco::GeometryAttribute::GENERIC, nullptr, 1, vid_type, false, draco::DataTypeLength(vid_type),
            0);
    const int id = dm.AddAttribute(ga, true, m.num_vertices());
    for (uint32_t v = 0; v < m.num_vertices(); ++v) {
      const uint32_t u = (*vid)[v];
      const float f = float(u);
      dm.attribute(id)->SetAttributeValue(draco::AttributeValueIndex(v),
                                          vid_type == draco::DT_FLOAT32 ? (const void*)&f : &u);
    }
    auto md = std::make_unique<draco::AttributeMetadata>();
    md->AddEntryString("name", kVertexIdAttribute);
    dm.AddAttributeMetadata(id, std::move(md));
  }
  draco::Encoder enc;
  draco::EncoderBuffer buf;
  const draco::Status s = cloud ? enc.EncodePointCloudToBuffer(dm, &buf) : enc.EncodeMeshToBuffer(dm, &buf);
  EXPECT_TRUE(s.ok()) << s.error_msg_string();
  return {buf.data(), buf.size()};
}

TEST(FrameCodecErrors, PlainDracoMeshIsASingleChunkFrame) {
  const Mesh m = test_wire::make_bumpy_grid(12, 9);
  const std::vector<std::string> chunks{plain_draco(m)};
  Mesh out;
  ASSERT_TRUE(decode(chunks, 0, out).ok());
  ASSERT_EQ(out.num_vertices(), m.num_vertices());
  ASSERT_EQ(out.num_triangles(), m.num_triangles());
  // Draco reorders points: map decoded vertices back through their (exact) positions.
  std::map<std::array<float, 3>, uint32_t> by_position;
  for (uint32_t v = 0; v < m.num_vertices(); ++v)
    by_position[{m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]}] = v;
  std::vector<uint32_t> mapped;
  for (uint32_t v : out.triangles) {
    const auto it =
        by_position.find({out.positions[3 * v], out.positions[3 * v + 1], out.positions[3 * v + 2]});
    ASSERT_NE(it, by_position.end());
    mapped.push_back(it->second);
  }
  EXPECT_EQ(triangle_set(mapped), triangle_set(m.triangles));
  std::vector<uint32_t> counts;  // one chunk of every triangle
  ASSERT_TRUE(decode_frame({chunks[0]}, 0, CodecOptions{}, out, nullptr, &counts).ok());
  EXPECT_EQ(counts, std::vector<uint32_t>{m.num_triangles()});
  EXPECT_TRUE(decode(chunks, m.num_vertices(), out).ok());
  EXPECT_EQ(decode(chunks, m.num_vertices() + 1, out).code(), StatusCode::kInvalidInput);
}

TEST(FrameCodecErrors, PlainMeshCannotJoinAMultiChunkFrame) {
  const Mesh m = test_wire::make_bumpy_grid(8, 8);
  std::vector<std::string> chunks = encode(m, 2);
  chunks[1] = plain_draco(m);
  Mesh out;
  const Status s = decode(chunks, m.num_vertices(), out);
  EXPECT_EQ(s.code(), StatusCode::kInvalidInput);
  EXPECT_NE(s.message().find("fq_vid"), std::string::npos) << s.message();
}

/// A two-chunk frame of `m` whose second chunk is `m` again, carrying `runs` as its id runs and
/// coded with Draco's sequential coder or edgebreaker.
std::vector<std::string> frame_with_forged_runs(const Mesh& m, const std::vector<uint8_t>& runs,
                                                bool sequential) {
  std::vector<std::string> chunks = encode(m, 2);
  draco::Mesh dm;
  fill_draco_mesh(m, dm);
  auto md = std::make_unique<draco::GeometryMetadata>();
  md->AddEntryBinary(kVertexIdRunsEntry, runs);
  dm.AddMetadata(std::move(md));
  draco::Encoder enc;
  enc.SetEncodingMethod(sequential ? draco::MESH_SEQUENTIAL_ENCODING : draco::MESH_EDGEBREAKER_ENCODING);
  draco::EncoderBuffer buf;
  EXPECT_TRUE(enc.EncodeMeshToBuffer(dm, &buf).ok());
  chunks[1].assign(buf.data(), buf.size());
  return chunks;
}

TEST(FrameCodecErrors, IdRunsNeedTheSequentialCoderAndOneIdPerPoint) {
  const Mesh m = test_wire::make_bumpy_grid(6, 6);
  const auto n = static_cast<uint8_t>(m.num_vertices());  // 36: one varint byte
  Mesh out;
  // Runs (gap 0, n points) name every vertex in order: valid when point order is kept.
  EXPECT_TRUE(decode(frame_with_forged_runs(m, {0, n}, true), m.num_vertices(), out).ok());
  Status s = decode(frame_with_forged_runs(m, {0, n}, false), m.num_vertices(), out);
  EXPECT_EQ(s.code(), StatusCode::kInvalidInput);
  EXPECT_NE(s.message().find("not sequentially coded"), std::string::npos) << s.message();
  for (const std::vector<uint8_t>& bad :
       {std::vector<uint8_t>{0, uint8_t(n - 1)}, std::vector<uint8_t>{0, 0}, std::vector<uint8_t>{0, 0x80},
        std::vector<uint8_t>{0xff, 0xff, 0xff, 0xff, 0x7f, 1}}) {
    s = decode(frame_with_forged_runs(m, bad, true), m.num_vertices(), out);
    EXPECT_EQ(s.code(), StatusCode::kInvalidInput);
    EXPECT_NE(s.message().find(kVertexIdRunsEntry), std::string::npos) << s.message();
  }
}

TEST(FrameCodecErrors, PointCloudRejected) {
  Mesh out;
  const Status s = decode({plain_draco(test_wire::make_bumpy_grid(3, 3), true)}, 0, out);
  EXPECT_EQ(s.code(), StatusCode::kInvalidInput);
  EXPECT_NE(s.message().find("point cloud"), std::string::npos) << s.message();
}

TEST(FrameCodecErrors, TruncatedOrGarbageChunkRejected) {
  const Mesh m = test_wire::make_bumpy_grid(10, 10);
  const std::vector<std::string> chunks = encode(m, 2);
  Mesh out;
  for (size_t keep : {size_t(0), size_t(5), size_t(20), chunks[1].size() / 2, chunks[1].size() - 1}) {
    std::vector<std::string> cut = chunks;
    cut[1].resize(keep);
    const Status s = decode(cut, m.num_vertices(), out);
    EXPECT_EQ(s.code(), StatusCode::kInvalidInput) << "kept " << keep << " bytes";
    EXPECT_NE(s.message().find("chunk 1"), std::string::npos) << s.message();
  }
  EXPECT_EQ(decode({std::string("not draco at all")}, 0, out).code(), StatusCode::kInvalidInput);
  EXPECT_EQ(decode({}, 0, out).code(), StatusCode::kInvalidInput);
}

TEST(FrameCodecErrors, VertexIdOutOfRangeRejected) {
  const Mesh m = test_wire::make_bumpy_grid(10, 10);
  Mesh out;
  const Status s = decode(encode(m, 3), m.num_vertices() - 1, out);
  EXPECT_EQ(s.code(), StatusCode::kInvalidInput);
  EXPECT_NE(s.message().find("out of range"), std::string::npos) << s.message();
}

TEST(FrameCodecErrors, MissingChunkRejected) {
  const Mesh m = test_wire::make_bumpy_grid(16, 16);
  std::vector<std::string> chunks = encode(m, 4);
  Mesh out;
  ASSERT_TRUE(decode(chunks, m.num_vertices(), out).ok());
  chunks.erase(chunks.begin() + 1);
  EXPECT_EQ(decode(chunks, m.num_vertices(), out).code(), StatusCode::kInvalidInput);
  EXPECT_EQ(decode(chunks, 0, out).code(), StatusCode::kInvalidInput);
  // With a huge count, too: the check must not allocate for a forged vertex_count.
  EXPECT_EQ(decode(chunks, 0xffffffffu, out).code(), StatusCode::kInvalidInput);
}

TEST(FrameCodecErrors, VertexNeverCoveredNamesTheVertex) {
  // Two chunks that together cover every vertex but one, with vertex_count saying so.
  const Mesh m = test_wire::make_bumpy_grid(16, 16);
  std::vector<std::string> chunks = encode(m, 2);
  chunks.push_back(chunks[0]);  // a repeated chunk adds points but covers nothing new
  chunks.erase(chunks.begin() + 1);
  Mesh out;
  const Status s = decode(chunks, m.num_vertices(), out);
  EXPECT_EQ(s.code(), StatusCode::kInvalidInput);
  EXPECT_NE(s.message().find("in no chunk"), std::string::npos) << s.message();
}

TEST(FrameCodecErrors, VertexCountZeroIsInferredFromTheIds) {
  const Mesh m = test_wire::make_bumpy_grid(9, 7);
  Mesh out;
  ASSERT_TRUE(decode(encode(m, 3), 0, out).ok());
  EXPECT_EQ(out.num_vertices(), m.num_vertices());
  EXPECT_EQ(triangle_set(out.triangles), triangle_set(m.triangles));
}

TEST(FrameCodecErrors, ForeignFqVidChunks) {
  // Chunks from another producer that uses fq_vid: ids are honoured, bad ones are caught.
  const Mesh m = test_wire::make_bumpy_grid(3, 3);
  std::vector<uint32_t> vid(m.num_vertices());
  for (uint32_t v = 0; v < vid.size(); ++v) vid[v] = uint32_t(vid.size()) - 1 - v;  // reversed
  Mesh out;
  ASSERT_TRUE(decode({plain_draco(m, false, &vid)}, m.num_vertices(), out).ok());
  for (uint32_t v = 0; v < m.num_vertices(); ++v) EXPECT_EQ(out.positions[3 * vid[v]], m.positions[3 * v]);
  vid[5] = 1000;  // out of range, with the count inferred: more vertices than points
  Status s = decode({plain_draco(m, false, &vid)}, 0, out);
  EXPECT_EQ(s.code(), StatusCode::kInvalidInput);
  vid[5] = vid[6];  // two points claim one id: one id is never covered
  s = decode({plain_draco(m, false, &vid)}, m.num_vertices(), out);
  EXPECT_EQ(s.code(), StatusCode::kInvalidInput);
  EXPECT_NE(s.message().find("in no chunk"), std::string::npos) << s.message();
  for (uint32_t v = 0; v < vid.size(); ++v) vid[v] = v;
  s = decode({plain_draco(m, false, &vid, draco::DT_FLOAT32)}, 0, out);
  EXPECT_EQ(s.code(), StatusCode::kInvalidInput);
  EXPECT_NE(s.message().find("uint32"), std::string::npos) << s.message();
}

TEST(FrameCodecErrors, LabelsOnlyWhenEveryChunkHasThem) {
  const Mesh m = test_wire::make_bumpy_grid(8, 8);
  std::vector<uint32_t> labels(m.num_vertices(), 4);
  std::vector<std::string> with, without;
  ASSERT_TRUE(encode_frame(m.view(), labels.data(), 2, CodecOptions{}, with).ok());
  ASSERT_TRUE(encode_frame(m.view(), nullptr, 2, CodecOptions{}, without).ok());
  std::vector<std::string_view> mixed{with[0], without[1]};
  Mesh out;
  std::vector<uint32_t> got{9};
  ASSERT_TRUE(decode_frame(mixed, m.num_vertices(), CodecOptions{}, out, &got).ok());
  EXPECT_TRUE(got.empty());
}

TEST(FrameCodecErrors, BadEncodeInputRejected) {
  Mesh m = test_wire::make_bumpy_grid(4, 4);
  std::vector<std::string> out;
  EXPECT_EQ(encode_frame(m.view(), nullptr, 0, CodecOptions{}, out).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(encode_frame(m.view(), nullptr, kMaxChunks + 1, CodecOptions{}, out).code(),
            StatusCode::kInvalidArgument);
  CodecOptions bad;
  bad.position_bits = 31;
  EXPECT_EQ(encode_frame(m.view(), nullptr, 1, bad, out).code(), StatusCode::kInvalidArgument);
  Mesh isolated = m;
  isolated.positions.insert(isolated.positions.end(), {9.f, 9.f, 9.f});
  const Status s = encode_frame(isolated.view(), nullptr, 1, CodecOptions{}, out);
  EXPECT_EQ(s.code(), StatusCode::kInvalidInput);
  EXPECT_NE(s.message().find("used by no triangle"), std::string::npos) << s.message();
  std::vector<uint32_t> labels(m.num_vertices(), 0);
  labels[3] = kMaxAttributeValue;
  EXPECT_EQ(encode_frame(m.view(), labels.data(), 1, CodecOptions{}, out).code(),
            StatusCode::kInvalidArgument);
  Mesh broken = m;
  broken.triangles[4] = 1000;
  EXPECT_EQ(encode_frame(broken.view(), nullptr, 2, CodecOptions{}, out).code(), StatusCode::kInvalidInput);
  EXPECT_TRUE(out.empty());
}

TEST(FrameCodecErrors, NonFiniteCoordinateOrBadIndexIsNamed) {
  // 20,301 vertices: two blocks of the box pass, and vertices in its four-at-a-time part and in
  // its remainder; the message names the first fault, as check_mesh does.
  const Mesh m = test_wire::make_bumpy_grid(200, 100);
  std::vector<std::string> out;
  const uint32_t last = m.num_vertices() - 1;
  for (uint32_t v : {0u, 5u, 16384u, 20000u, last}) {
    for (float bad : {std::numeric_limits<float>::quiet_NaN(), -std::numeric_limits<float>::infinity()}) {
      Mesh broken = m;
      broken.positions[3 * size_t(v) + v % 3] = bad;
      const Status s = encode_frame(broken.view(), nullptr, 4, CodecOptions{}, out);
      EXPECT_EQ(s.code(), StatusCode::kInvalidInput);
      EXPECT_NE(s.message().find("vertex " + std::to_string(v) + " has a non-finite coordinate"),
                std::string::npos)
          << s.message();
      EXPECT_TRUE(out.empty());
    }
  }
  for (uint32_t t : {0u, 7000u, m.num_triangles() - 1}) {
    Mesh broken = m;
    broken.triangles[3 * size_t(t) + 2] = m.num_vertices();
    const Status s = encode_frame(broken.view(), nullptr, 4, CodecOptions{}, out);
    EXPECT_EQ(s.code(), StatusCode::kInvalidInput);
    EXPECT_NE(s.message().find("triangle " + std::to_string(t) + " references vertex"), std::string::npos)
        << s.message();
  }
}

}  // namespace
}  // namespace fq::wire
