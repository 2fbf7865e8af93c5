// Chunked Draco frames: split, encode, decode and merge give back the input mesh.
#include "wire/frame_codec.h"

#include <draco/compression/decode.h>
#include <draco/mesh/mesh.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <thread>

#include "tests/wire/wire_test_meshes.h"
#include "wire/frame_split.h"

namespace fq::wire {
namespace {

using test_wire::triangle_set;

std::vector<std::string_view> views(const std::vector<std::string>& chunks) {
  return {chunks.begin(), chunks.end()};
}

/// Encodes `m` in `chunks` chunks and decodes it back (on `threads` threads both ways, at
/// Draco speed `speed`: 10 is the sequential coder with ids as runs, lower speeds edgebreaker).
Mesh round_trip(const Mesh& m, uint32_t chunks, int threads = 2, const uint32_t* labels = nullptr,
                std::vector<uint32_t>* labels_out = nullptr, int speed = 5) {
  CodecOptions o;
  o.threads = threads;
  o.encode_speed = o.decode_speed = speed;
  std::vector<std::string> encoded;
  const Status es = encode_frame(m.view(), labels, chunks, o, encoded);
  EXPECT_TRUE(es.ok()) << es.message();
  EXPECT_EQ(encoded.size(), std::min(chunks, m.num_triangles()));
  Mesh out;
  const Status ds = decode_frame(views(encoded), m.num_vertices(), o, out, labels_out);
  EXPECT_TRUE(ds.ok()) << ds.message();
  return out;
}

/// Same vertex count, same triangles (by global id, orientation kept), positions within half a
/// 16-bit quantization step of the frame's bounding box.
void expect_same_mesh(const Mesh& in, const Mesh& out) {
  ASSERT_EQ(out.num_vertices(), in.num_vertices());
  EXPECT_EQ(triangle_set(out.triangles), triangle_set(in.triangles));
  float lo[3], hi[3];
  for (int a = 0; a < 3; ++a) lo[a] = hi[a] = in.positions[a];
  for (size_t i = 0; i < in.positions.size(); ++i) {
    lo[i % 3] = std::min(lo[i % 3], in.positions[i]);
    hi[i % 3] = std::max(hi[i % 3], in.positions[i]);
  }
  const float extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  const float tolerance = 0.5f * extent / 65535.f * 1.01f + 1e-6f * extent;
  float worst = 0.f;
  for (size_t i = 0; i < in.positions.size(); ++i)
    worst = std::max(worst, std::abs(in.positions[i] - out.positions[i]));
  EXPECT_LE(worst, tolerance);
}

void check_chunk_counts(const Mesh& m, int speed = 5) {
  const Mesh whole = round_trip(m, 1, 2, nullptr, nullptr, speed);
  expect_same_mesh(m, whole);
  for (uint32_t chunks : {2u, 4u, 7u}) {
    SCOPED_TRACE("chunks " + std::to_string(chunks) + ", speed " + std::to_string(speed));
    const Mesh split = round_trip(m, chunks, 2, nullptr, nullptr, speed);
    expect_same_mesh(m, split);
    EXPECT_EQ(split.positions, whole.positions);  // one quantization grid: bit for bit
  }
}

TEST(FrameCodec, MeshMadeInCodeAnyChunkCount) { check_chunk_counts(test_wire::make_bumpy_grid(40, 30)); }

TEST(FrameCodec, RealMeshAnyChunkCount) {
  const auto m = test_wire::load_shared_mesh("bunny.ply");
  if (!m) GTEST_SKIP() << "bunny.ply not found (set FQ_MESH_DIR)";
  check_chunk_counts(*m);
  check_chunk_counts(*m, 10);
}

TEST(FrameCodec, SequentialChunksCarryIdRunsEdgebreakerChunksAnAttribute) {
  const Mesh m = test_wire::make_bumpy_grid(30, 20);
  for (int speed : {5, 10}) {
    CodecOptions o;
    o.encode_speed = o.decode_speed = speed;
    std::vector<std::string> encoded;
    ASSERT_TRUE(encode_frame(m.view(), nullptr, 3, o, encoded).ok());
    for (const std::string& chunk : encoded) {
      draco::DecoderBuffer buf;
      buf.Init(chunk.data(), chunk.size());
      draco::Decoder dec;
      auto dm = dec.DecodeMeshFromBuffer(&buf);
      ASSERT_TRUE(dm.ok());
      const bool attribute = dm.value()->GetAttributeIdByMetadataEntry("name", kVertexIdAttribute) >= 0;
      std::vector<uint8_t> runs;
      const bool has_runs = dm.value()->GetMetadata() != nullptr &&
                            dm.value()->GetMetadata()->GetEntryBinary(kVertexIdRunsEntry, &runs);
      EXPECT_EQ(attribute, speed != 10) << "speed " << speed;
      EXPECT_EQ(has_runs, speed == 10) << "speed " << speed;
      // A 30 x 20 grid's chunk is a few rows: its ids are a few runs, far below 1 byte per point.
      if (has_runs) {
        EXPECT_LT(runs.size(), dm.value()->num_points() / 4);
      }
    }
  }
}

TEST(FrameCodec, ThreadCountDoesNotChangeTheResult) {
  const Mesh m = test_wire::make_bumpy_grid(30, 30);
  const Mesh a = round_trip(m, 5, 1);
  const Mesh b = round_trip(m, 5, 3);
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.triangles, b.triangles);
}

// The codec keeps its buffers per use, not per thread (they were thread_local: one set for
// every thread that ever encoded or decoded, out of reach of anyone who wanted the memory
// back). Frames from threads that come and go share one set, which release_memory frees.
TEST(FrameCodec, ReleaseMemoryReachesTheBuffersOfEveryThread) {
  const Mesh m = test_wire::make_bumpy_grid(40, 30);
  CodecOptions o;
  o.threads = 1;
  o.encode_speed = o.decode_speed = 10;
  release_memory();  // what earlier tests of this process kept
  for (int t = 0; t < 4; ++t) {
    std::thread([&] {
      std::vector<std::string> chunks, points;
      ASSERT_TRUE(encode_frame(m.view(), nullptr, 2, o, chunks).ok());
      Mesh out;
      ASSERT_TRUE(decode_frame(views(chunks), 0, o, out, nullptr).ok());
      ASSERT_TRUE(encode_positions(m.positions.data(), m.num_vertices(), 2, o, points).ok());
      std::vector<float> positions;
      ASSERT_TRUE(decode_positions(views(points), m.num_vertices(), o, positions).ok());
    }).join();
  }
  // One at a time, so one of each: a chunk writer's, a sequential coder's, a frame's decoded chunks.
  EXPECT_EQ(release_memory(), 3u);
  EXPECT_EQ(release_memory(), 0u);
  EXPECT_EQ(round_trip(m, 3).positions.size(), m.positions.size()) << "the codec works after a release";
}

// fqd decodes every frame of a stream into a pooled mesh: a reused mesh must come out exactly
// as a fresh one (no stale vertex from the previous frame), keep its buffers when the next
// frame has the same size, and be empty after a frame that fails.
TEST(FrameCodec, DecodingIntoAReusedMeshMatchesAFreshOne) {
  const Mesh a = test_wire::make_bumpy_grid(40, 30), b = test_wire::make_bumpy_grid(25, 20);
  CodecOptions o;
  o.threads = 2;
  std::vector<std::string> ea, eb;
  ASSERT_TRUE(encode_frame(a.view(), nullptr, 4, o, ea).ok());
  ASSERT_TRUE(encode_frame(b.view(), nullptr, 3, o, eb).ok());
  const Mesh fresh_a = round_trip(a, 4), fresh_b = round_trip(b, 3);
  Mesh reused;
  ASSERT_TRUE(decode_frame(views(ea), 0, o, reused, nullptr).ok());
  const float* positions = reused.positions.data();
  const uint32_t* triangles = reused.triangles.data();
  ASSERT_TRUE(decode_frame(views(ea), 0, o, reused, nullptr).ok());
  EXPECT_EQ(reused.positions.data(), positions);  // same size: the buffers were kept
  EXPECT_EQ(reused.triangles.data(), triangles);
  EXPECT_EQ(reused.positions, fresh_a.positions);
  EXPECT_EQ(reused.triangles, fresh_a.triangles);
  ASSERT_TRUE(decode_frame(views(eb), 0, o, reused, nullptr).ok());  // a smaller frame next
  EXPECT_EQ(reused.positions, fresh_b.positions);
  EXPECT_EQ(reused.triangles, fresh_b.triangles);
  std::vector<std::string> missing(eb.begin(), eb.end() - 1);  // a chunk lost: vertices uncovered
  EXPECT_FALSE(decode_frame(views(missing), b.num_vertices(), o, reused, nullptr).ok());
  EXPECT_EQ(reused.num_vertices(), 0u);
  EXPECT_EQ(reused.num_triangles(), 0u);
}

TEST(FrameCodec, ChunksAreSpatiallyCoherent) {
  // Border vertices appear in every chunk that uses them: a coherent split of a 64 x 8 strip
  // into 4 repeats only vertices along the 3 cuts (at most two columns of 9 each, as a
  // triangle goes with its lowest vertex and a cut may step by one column), a scattered one
  // would repeat most vertices.
  const Mesh m = test_wire::make_bumpy_grid(64, 8);
  const auto parts = detail::split_parts(m.view(), detail::bounding_box(m.view()), 4);
  ASSERT_EQ(parts.size(), 4u);
  size_t vertices = 0;
  std::vector<int> owner(m.num_triangles(), -1);
  for (size_t c = 0; c < parts.size(); ++c) {
    EXPECT_EQ(parts[c].triangles, m.num_triangles() / 4);
    uint32_t in_runs = 0, next = 0;
    std::vector<uint32_t> used;
    for (const detail::TriangleRun& r : parts[c].runs) {
      EXPECT_GE(r.first, next);  // ascending, apart: the input order is kept
      EXPECT_GT(r.count, 0u);
      next = r.first + r.count + 1;
      in_runs += r.count;
      for (uint32_t t = r.first; t < r.first + r.count; ++t) {
        EXPECT_EQ(owner[t], -1) << "triangle " << t << " in two parts";
        owner[t] = int(c);
        used.insert(used.end(), &m.triangles[3 * size_t(t)], &m.triangles[3 * size_t(t)] + 3);
      }
    }
    EXPECT_EQ(in_runs, parts[c].triangles);
    std::sort(used.begin(), used.end());
    vertices += size_t(std::unique(used.begin(), used.end()) - used.begin());
  }
  EXPECT_EQ(std::count(owner.begin(), owner.end(), -1), 0);
  EXPECT_LE(vertices, m.num_vertices() + 3 * 2 * 9);
}

TEST(FrameCodec, TheSplitDoesNotDependOnTheThreads) {
  const Mesh m = test_wire::make_bumpy_grid(150, 120);  // 36,000 triangles: several blocks
  const detail::Box box = detail::bounding_box(m.view());
  const auto one = detail::split_parts(m.view(), box, 7, 1);
  for (int threads : {2, 3}) {
    const auto more = detail::split_parts(m.view(), box, 7, threads);
    ASSERT_EQ(more.size(), one.size());
    for (size_t c = 0; c < one.size(); ++c) {
      EXPECT_EQ(more[c].triangles, one[c].triangles);
      ASSERT_EQ(more[c].runs.size(), one[c].runs.size()) << threads << " threads, part " << c;
      for (size_t k = 0; k < one[c].runs.size(); ++k) {
        EXPECT_EQ(more[c].runs[k].first, one[c].runs[k].first);
        EXPECT_EQ(more[c].runs[k].count, one[c].runs[k].count);
      }
    }
  }
}

TEST(FrameCodec, AResultIsCutAsItsInputWas) {
  // decode_frame lays the chunks' triangles out one chunk after the other and says how many
  // each had; encode_frame_as cuts a mesh with that connectivity the same way, without a split.
  const Mesh m = test_wire::make_bumpy_grid(30, 20);
  for (int speed : {10, 5}) {
    CodecOptions o;
    o.threads = 2;
    o.encode_speed = o.decode_speed = speed;
    std::vector<std::string> encoded;
    ASSERT_TRUE(encode_frame(m.view(), nullptr, 4, o, encoded).ok());
    Mesh input;
    std::vector<uint32_t> counts;
    ASSERT_TRUE(decode_frame(views(encoded), m.num_vertices(), o, input, nullptr, &counts).ok());
    ASSERT_EQ(counts.size(), 4u);
    uint32_t total = 0;
    for (uint32_t c : counts) total += c;
    EXPECT_EQ(total, input.num_triangles());
    Mesh moved = input;  // a filtered result: new positions, the input's faces
    for (size_t i = 0; i < moved.positions.size(); ++i) moved.positions[i] += 0.01f * float(i % 7);
    std::vector<uint32_t> labels(moved.num_vertices());
    for (uint32_t v = 0; v < labels.size(); ++v) labels[v] = v % 5;
    std::vector<std::string> result;
    const Status es = encode_frame_as(moved.view(), labels.data(), counts, o, result);
    ASSERT_TRUE(es.ok()) << es.message();
    ASSERT_EQ(result.size(), counts.size());
    Mesh back;
    std::vector<uint32_t> back_counts, back_labels;
    ASSERT_TRUE(decode_frame(views(result), moved.num_vertices(), o, back, &back_labels, &back_counts).ok());
    EXPECT_EQ(back_counts, counts) << "speed " << speed;
    EXPECT_EQ(back_labels, labels);
    expect_same_mesh(moved, back);
    // The sequential coder keeps face and point order: the very same chunk meshes come back.
    if (speed == 10) EXPECT_EQ(back.triangles, input.triangles);
  }
}

TEST(FrameCodec, ChunkCountsMustDescribeTheMesh) {
  const Mesh m = test_wire::make_bumpy_grid(6, 5);  // 60 triangles
  std::vector<std::string> out;
  const CodecOptions o;
  for (const std::vector<uint32_t>& counts : std::vector<std::vector<uint32_t>>{
           {}, {30, 0, 30}, {30, 20}, {30, 40}, std::vector<uint32_t>(kMaxChunks + 1, 1)}) {
    const Status s = encode_frame_as(m.view(), nullptr, counts, o, out);
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument) << counts.size() << " chunks: " << s.message();
    EXPECT_TRUE(out.empty());
  }
  Mesh broken = m;
  broken.positions[4] = std::nanf("");
  EXPECT_EQ(encode_frame_as(broken.view(), nullptr, {20, 40}, o, out).code(), StatusCode::kInvalidInput);
  EXPECT_TRUE(encode_frame_as(m.view(), nullptr, {20, 40}, o, out).ok());
  EXPECT_EQ(out.size(), 2u);
  // A failed decode leaves no counts behind.
  Mesh back;
  std::vector<uint32_t> counts{7, 7};
  EXPECT_FALSE(decode_frame(views({out[0]}), m.num_vertices(), o, back, nullptr, &counts).ok());
  EXPECT_TRUE(counts.empty());
}

TEST(FrameCodec, LabelsRoundTrip) {
  const Mesh m = test_wire::make_bumpy_grid(20, 20);
  std::vector<uint32_t> labels(m.num_vertices());
  for (uint32_t v = 0; v < labels.size(); ++v)
    labels[v] = v % 3 == 0 ? kMaxAttributeValue - 1 - v : (v * 7919u) % 1000003u;
  for (uint32_t chunks : {1u, 3u}) {
    std::vector<uint32_t> out;
    const Mesh back = round_trip(m, chunks, 2, labels.data(), &out);
    EXPECT_EQ(out, labels) << chunks << " chunks";
  }
  std::vector<uint32_t> none{1, 2, 3};
  round_trip(m, 2, 2, nullptr, &none);
  EXPECT_TRUE(none.empty());  // no fq_label: labels cleared, not stale
}

TEST(FrameCodec, DuplicatePositionsStayDistinctVertices) {
  const Mesh soup = test_wire::make_soup(test_wire::make_bumpy_grid(6, 5));
  for (uint32_t chunks : {1u, 3u}) {
    const Mesh back = round_trip(soup, chunks);
    expect_same_mesh(soup, back);
  }
  // Two vertices at exactly the same point, both used, like dragon.ply.
  Mesh pair = test_wire::make_bumpy_grid(2, 2);
  pair.positions.insert(pair.positions.end(), pair.positions.begin() + 3 * 4,
                        pair.positions.begin() + 3 * 4 + 3);
  pair.triangles[0] = 9;  // triangle 0 now uses vertex 9, at exactly vertex 4's position
  const Mesh back = round_trip(pair, 1);
  expect_same_mesh(pair, back);
}

TEST(FrameCodec, NonManifoldFinRoundTrips) {
  Mesh fin;
  fin.positions = {0, 0, 0, 1, 0, 0, 0.5f, 1, 0, 0.5f, -1, 0, 0.5f, 0, 1};
  fin.triangles = {0, 1, 2, 1, 0, 3, 0, 1, 4};
  for (uint32_t chunks : {1u, 2u, 3u}) expect_same_mesh(fin, round_trip(fin, chunks));
}

TEST(FrameCodec, MoreChunksThanTrianglesIsClamped) {
  const Mesh m = test_wire::make_bumpy_grid(1, 1);
  expect_same_mesh(m, round_trip(m, 9));
}

TEST(FrameCodec, ZeroAreaAndRepeatedTrianglesAreKept) {
  // Draco's edgebreaker drops a face with a repeated index: the codec must not lose it, nor a
  // collinear face, nor a face given twice (once each way).
  Mesh m = test_wire::make_bumpy_grid(4, 4);
  m.positions.insert(m.positions.end(), {0.05f, 0.f, 0.f});  // midpoint of edge (0, 1)
  const uint32_t mid = m.num_vertices() - 1;
  m.triangles.insert(m.triangles.end(), {0, 0, 1, 0, mid, 1, 7, 8, 13, 7, 13, 8});
  for (uint32_t chunks : {1u, 2u, 5u}) {
    CodecOptions o;
    std::vector<std::string> encoded;
    ASSERT_TRUE(encode_frame(m.view(), nullptr, chunks, o, encoded).ok());
    Mesh out;
    std::vector<std::string_view> v(encoded.begin(), encoded.end());
    const Status s = decode_frame(v, m.num_vertices(), o, out, nullptr);
    ASSERT_TRUE(s.ok()) << s.message();
    EXPECT_EQ(test_wire::triangle_set(out.triangles), test_wire::triangle_set(m.triangles)) << chunks;
  }
}

class FrameCodecSpeed : public ::testing::TestWithParam<int> {};

TEST_P(FrameCodecSpeed, RoundTripWithLabelsAtEveryDracoSpeed) {
  // Speed 10 selects Draco's sequential coder, lower speeds edgebreaker: both must round trip.
  const Mesh m = test_wire::make_bumpy_grid(24, 17);
  std::vector<uint32_t> labels(m.num_vertices());
  for (uint32_t v = 0; v < labels.size(); ++v) labels[v] = (v / 7) % 11;
  CodecOptions o;
  o.encode_speed = o.decode_speed = GetParam();
  o.threads = 2;
  std::vector<float> unchunked;
  for (uint32_t chunks : {1u, 3u}) {
    std::vector<std::string> encoded;
    ASSERT_TRUE(encode_frame(m.view(), labels.data(), chunks, o, encoded).ok());
    std::vector<std::string_view> v(encoded.begin(), encoded.end());
    Mesh out;
    std::vector<uint32_t> got;
    ASSERT_TRUE(decode_frame(v, m.num_vertices(), o, out, &got).ok());
    expect_same_mesh(m, out);
    EXPECT_EQ(got, labels);
    if (chunks == 1) unchunked = out.positions;
    EXPECT_EQ(out.positions, unchunked);
  }
}

INSTANTIATE_TEST_SUITE_P(Speeds, FrameCodecSpeed, ::testing::Values(0, 5, 7, 10));

TEST(FrameCodec, DragonKeepsItsCoincidentVertices) {
  // dragon.ply was quantized to 11 bits upstream: 51,986 of its vertices share a position with
  // another vertex, and 105K faces have zero area. A deduplicating codec would merge them.
  const auto m = test_wire::load_shared_mesh("dragon.ply");
  if (!m) GTEST_SKIP() << "dragon.ply not found (set FQ_MESH_DIR)";
  expect_same_mesh(*m, round_trip(*m, 4, 2));
  expect_same_mesh(*m, round_trip(*m, 4, 2, nullptr, nullptr, 10));  // sequential coder, id runs
}

TEST(FrameCodec, EdgebreakerKeepsRepeatedAndCollinearFaces) {
  // No face repeats a vertex here, so every chunk goes through edgebreaker (speed 5).
  Mesh m = test_wire::make_bumpy_grid(4, 4);
  m.positions.insert(m.positions.end(), {0.05f, 0.f, 0.f});  // midpoint of edge (0, 1)
  const uint32_t mid = m.num_vertices() - 1;
  m.triangles.insert(m.triangles.end(), {0, mid, 1, 7, 8, 13, 7, 13, 8});
  for (uint32_t chunks : {1u, 2u}) expect_same_mesh(m, round_trip(m, chunks));
}

}  // namespace
}  // namespace fq::wire
