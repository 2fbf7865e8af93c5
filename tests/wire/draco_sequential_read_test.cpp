// read_sequential_chunk and read_sequential_point_cloud against Draco's decoder: on the
// codec's own chunks they must give what Draco gives, and on anything else (other layouts,
// damaged bytes) either give what Draco gives or leave the chunk to Draco. Never a different
// reading, never a chunk Draco refuses.
#include "wire/draco_sequential_read.h"

#include <draco/compression/decode.h>
#include <draco/mesh/mesh.h>
#include <draco/metadata/geometry_metadata.h>
#include <draco/point_cloud/point_cloud.h>
#include <gtest/gtest.h>

#include <cstring>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "tests/wire/wire_test_meshes.h"
#include "wire/draco_sequential.h"
#include "wire/frame_chunk.h"
#include "wire/frame_split.h"
#include "wire/vertex_id_runs.h"

namespace fq::wire::detail {
namespace {

/// A chunk as Draco's decoder and decode_frame's Draco path read it.
struct DracoReading {
  bool ok = false;
  std::vector<float> positions;
  std::vector<uint32_t> corners, ids, labels;
};

DracoReading read_with_draco(const std::string& bytes) {
  DracoReading r;
  draco::DecoderBuffer buf;
  buf.Init(bytes.data(), bytes.size());
  draco::Decoder dec;
  auto decoded = dec.DecodeMeshFromBuffer(&buf);
  if (!decoded.ok()) return r;
  const draco::Mesh& m = *decoded.value();
  const draco::PointAttribute* pos = m.GetNamedAttribute(draco::GeometryAttribute::POSITION);
  std::vector<uint8_t> runs;
  if (pos == nullptr || pos->num_components() != 3 || m.num_faces() == 0 || m.GetMetadata() == nullptr ||
      !m.GetMetadata()->GetEntryBinary(kVertexIdRunsEntry, &runs) ||
      !decode_id_runs(runs.data(), runs.size(), m.num_points(), kMaxAttributeValue, r.ids))
    return r;
  r.positions.resize(3 * size_t(m.num_points()));
  for (uint32_t p = 0; p < m.num_points(); ++p)
    pos->ConvertValue<float>(pos->mapped_index(draco::PointIndex(p)), 3, &r.positions[3 * size_t(p)]);
  for (draco::FaceIndex f(0); f < m.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      r.corners.push_back(m.face(f)[k].value());
      if (r.corners.back() >= m.num_points()) return r;  // decode_frame refuses such a face
    }
  if (const int id = m.GetAttributeIdByMetadataEntry("name", kLabelAttribute); id >= 0) {
    if (m.attribute(id)->num_components() != 1 || m.attribute(id)->data_type() != draco::DT_UINT32) return r;
    r.labels.resize(m.num_points());
    for (uint32_t p = 0; p < m.num_points(); ++p)
      m.attribute(id)->ConvertValue<uint32_t>(m.attribute(id)->mapped_index(draco::PointIndex(p)), 1,
                                              &r.labels[p]);
  }
  r.ok = true;
  return r;
}

/// Reads `bytes` both ways; when the direct reader takes them, Draco must read the same.
/// Returns whether the direct reader took them.
bool expect_same_reading(const std::string& bytes) {
  SequentialChunk c;
  const bool direct = read_sequential_chunk(bytes, kMaxAttributeValue, c);
  if (!direct) return false;
  const DracoReading d = read_with_draco(bytes);
  EXPECT_TRUE(d.ok) << "the direct reader took a chunk Draco's path refuses";
  if (!d.ok) return true;
  EXPECT_EQ(c.points * 3, d.positions.size());
  EXPECT_EQ(0, std::memcmp(c.positions.data(), d.positions.data(), d.positions.size() * sizeof(float)));
  EXPECT_EQ(c.corners, d.corners);
  EXPECT_EQ(c.ids, d.ids);
  EXPECT_EQ(c.labels, d.labels);
  return true;
}

std::vector<std::string> own_chunks(const Mesh& mesh, uint32_t chunks, bool with_labels) {
  CodecOptions o;
  o.encode_speed = o.decode_speed = 10;
  std::vector<uint32_t> labels(mesh.num_vertices());
  for (uint32_t v = 0; v < labels.size(); ++v) labels[v] = (v * 7919u) % 5000u;
  const MeshView view = mesh.view();
  const Box box = bounding_box(view);
  ChunkScratch scratch;
  std::vector<std::string> out;
  for (const Part& part : split_parts(view, box, chunks)) {
    out.emplace_back();
    EXPECT_TRUE(
        write_sequential_chunk(view, with_labels ? labels.data() : nullptr, part, o, box, scratch, out.back())
            .ok());
  }
  return out;
}

TEST(DracoSequentialRead, OwnChunksReadAsDracoReadsThem) {
  for (bool labels : {false, true}) {
    for (const Mesh& m : {test_wire::make_bumpy_grid(8, 6), test_wire::make_bumpy_grid(60, 40),
                          test_wire::make_bumpy_grid(300, 250)}) {  // uint8, uint16 and varint indices
      for (const std::string& chunk : own_chunks(m, 3, labels)) EXPECT_TRUE(expect_same_reading(chunk));
    }
  }
}

TEST(DracoSequentialRead, OtherLayoutsAreLeftToDraco) {
  const Mesh grid = test_wire::make_bumpy_grid(30, 20);
  const MeshView view = grid.view();
  const Box box = bounding_box(view);
  const Part all = split_parts(view, box, 1)[0];
  ChunkScratch scratch;
  CodecOptions edgebreaker;  // speed 5: Draco's edgebreaker coder, ids as an attribute
  draco::Mesh m;
  ASSERT_FALSE(build_chunk(view, nullptr, true, edgebreaker, all, scratch, m));
  std::string bytes;
  ASSERT_TRUE(encode_chunk(m, false, edgebreaker, box, bytes).ok());
  SequentialChunk c;
  EXPECT_FALSE(read_sequential_chunk(bytes, kMaxAttributeValue, c));
  // A sequential chunk without ids (a plain Draco mesh): decode_frame's single-chunk case.
  CodecOptions fast;
  fast.encode_speed = fast.decode_speed = 10;
  draco::Mesh plain;
  ASSERT_TRUE(build_chunk(view, nullptr, false, fast, all, scratch, plain));
  ASSERT_TRUE(encode_chunk(plain, true, fast, box, bytes).ok());
  EXPECT_FALSE(read_sequential_chunk(bytes, kMaxAttributeValue, c));
  // Ids at or past the limit.
  const std::string own = own_chunks(grid, 1, false)[0];
  EXPECT_TRUE(read_sequential_chunk(own, grid.num_vertices(), c));
  EXPECT_FALSE(read_sequential_chunk(own, grid.num_vertices() - 1, c));
  // Cut short anywhere.
  for (size_t n : {size_t(0), size_t(4), own.size() / 3, own.size() - 20, own.size() - 1})
    EXPECT_FALSE(read_sequential_chunk(own.substr(0, n), kMaxAttributeValue, c)) << n << " bytes";
}

TEST(DracoSequentialRead, DamagedChunksReadAsDracoReadsThemOrNotAtAll) {
  std::mt19937 rng(7);
  const std::vector<std::string> chunks = own_chunks(test_wire::make_bumpy_grid(24, 20), 2, true);
  int taken = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    std::string bytes = chunks[size_t(trial) % chunks.size()];
    const int flips = 1 + trial % 3;
    for (int k = 0; k < flips; ++k) {
      const size_t at = rng() % bytes.size();
      bytes[at] = static_cast<char>(bytes[at] ^ (1 << (rng() % 8)));
    }
    taken += expect_same_reading(bytes) ? 1 : 0;
  }
  // Some damage falls where it changes values, not the layout: those chunks are still read.
  EXPECT_GT(taken, 0);
}

/// A point cloud as Draco's decoder reads it: its positions, or nothing when it refuses it.
std::optional<std::vector<float>> cloud_with_draco(const std::string& bytes) {
  draco::DecoderBuffer buf;
  buf.Init(bytes.data(), bytes.size());
  draco::Decoder dec;
  auto decoded = dec.DecodePointCloudFromBuffer(&buf);
  if (!decoded.ok()) return std::nullopt;
  const draco::PointCloud& pc = *decoded.value();
  const draco::PointAttribute* pos = pc.GetNamedAttribute(draco::GeometryAttribute::POSITION);
  if (pos == nullptr || pos->num_components() != 3) return std::nullopt;
  std::vector<float> xyz(3 * size_t(pc.num_points()));
  for (uint32_t p = 0; p < pc.num_points(); ++p)
    pos->ConvertValue<float>(pos->mapped_index(draco::PointIndex(p)), 3, &xyz[3 * size_t(p)]);
  return xyz;
}

/// Reads a point cloud both ways; when the direct reader takes it, Draco must read the same.
bool expect_same_cloud(const std::string& bytes) {
  uint32_t n = 0;
  if (!sequential_point_count(bytes, n) || n > 1'000'000) return false;
  std::vector<float> ours(3 * size_t(n));
  std::vector<int32_t> values;
  if (!read_sequential_point_cloud(bytes, n, ours.data(), values)) return false;
  const auto by_draco = cloud_with_draco(bytes);
  EXPECT_TRUE(by_draco.has_value()) << "the direct reader took a point cloud Draco refuses";
  if (by_draco) {
    EXPECT_EQ(by_draco->size(), ours.size());
    EXPECT_EQ(0, std::memcmp(ours.data(), by_draco->data(),
                             std::min(ours.size(), by_draco->size()) * sizeof(float)));
  }
  return true;
}

TEST(DracoSequentialRead, PointCloudsReadAsDracoReadsThem) {
  const Mesh grid = test_wire::make_bumpy_grid(80, 60);
  const Box box = bounding_box(grid.view());
  SequentialScratch scratch;
  std::mt19937 rng(11);
  for (int speed : {5, 10}) {
    CodecOptions o;
    o.encode_speed = o.decode_speed = speed;
    std::string bytes;
    ASSERT_TRUE(write_point_cloud(grid.positions.data(), grid.num_vertices(), o, box, scratch, bytes).ok());
    EXPECT_TRUE(expect_same_cloud(bytes));
    uint32_t n = 0;
    EXPECT_FALSE(sequential_point_count(bytes.substr(0, 12), n));  // cut short in the header
    std::vector<float> out(3 * size_t(grid.num_vertices()));
    std::vector<int32_t> values;
    EXPECT_FALSE(read_sequential_point_cloud(bytes, grid.num_vertices() - 1, out.data(), values));
    EXPECT_FALSE(read_sequential_point_cloud(bytes.substr(0, bytes.size() - 1), grid.num_vertices(),
                                             out.data(), values));
    int taken = 0;
    for (int trial = 0; trial < 1000; ++trial) {
      std::string damaged = bytes;
      const size_t at = rng() % damaged.size();
      damaged[at] = static_cast<char>(damaged[at] ^ (1 << (rng() % 8)));
      taken += expect_same_cloud(damaged) ? 1 : 0;
    }
    EXPECT_GT(taken, 0);
  }
  // A mesh chunk is not a point cloud.
  uint32_t n = 0;
  EXPECT_FALSE(sequential_point_count(own_chunks(grid, 1, false)[0], n));
}

}  // namespace
}  // namespace fq::wire::detail
