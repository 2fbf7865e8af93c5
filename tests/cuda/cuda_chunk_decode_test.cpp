// The device decode (kernels/cuda/chunk_decoder.h) against the host reader
// (read_sequential_chunk): on every shared mesh at 1, 2, 7, 64 and 256 chunks, and on damaged
// chunks, the device takes exactly the chunks the host reader takes and decodes them to the
// same bits, in every form of the kernel (a block of 256 or 1024, a warp, a thread a chunk).
// Skips without a device.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "kernels/cuda/chunk_decoder.h"
#include "tests/support/shared_meshes.h"
#include "tests/wire/wire_test_meshes.h"
#include "wire/draco_sequential_read.h"
#include "wire/frame_codec.h"
#include "wire/sequential_layout.h"
#include "wire/symbol_decode.h"

namespace fq::test {
namespace {

using cuda::ChunkDecoder;
using cuda::ChunkTeam;

constexpr ChunkTeam kTeams[] = {ChunkTeam::kWideBlock, ChunkTeam::kBlock, ChunkTeam::kWarp,
                                ChunkTeam::kThread};

std::string team_name(ChunkTeam t) { return std::to_string(int(t)) + " thread(s) a chunk"; }

class CudaChunkDecode : public ::testing::Test {
 protected:
  void SetUp() override {
    if (const Status s = cuda::chunk_decoder_device(); !s.ok()) GTEST_SKIP() << s.message();
  }
};

std::vector<std::string_view> views(const std::vector<std::string>& chunks) {
  return {chunks.begin(), chunks.end()};
}

/// Decodes `chunks` on the device with `team` and expects each chunk to equal the host reader's
/// reading of it, bit for bit.
void expect_device_reads_as_host(ChunkTeam team, const std::vector<std::string>& chunks,
                                 const std::string& what) {
  ChunkDecoder dec(team);
  const Status s = dec.decode(views(chunks), wire::kMaxAttributeValue);
  ASSERT_TRUE(s.ok()) << what << ": " << s.message();
  std::vector<float> positions;
  std::vector<uint32_t> corners, labels;
  dec.download(positions, corners, labels);
  for (size_t i = 0; i < chunks.size(); ++i) {
    wire::detail::SequentialChunk host;
    ASSERT_TRUE(wire::detail::read_sequential_chunk(chunks[i], wire::kMaxAttributeValue, host)) << what;
    const cuda::ChunkJob& job = dec.plan().jobs[i];
    ASSERT_EQ(job.points, host.points) << what;
    ASSERT_EQ(job.faces, host.faces) << what;
    EXPECT_EQ(0, std::memcmp(positions.data() + 3 * job.first_point, host.positions.data(),
                             host.positions.size() * sizeof(float)))
        << what << ", chunk " << i << ": positions differ";
    EXPECT_EQ(0, std::memcmp(corners.data() + job.first_corner, host.corners.data(),
                             host.corners.size() * sizeof(uint32_t)))
        << what << ", chunk " << i << ": corners differ";
    EXPECT_EQ(dec.plan().ids[i], host.ids) << what << ", chunk " << i;
    ASSERT_EQ(job.labelled != 0, !host.labels.empty()) << what;
    if (job.labelled) {
      EXPECT_EQ(0, std::memcmp(labels.data() + job.first_point, host.labels.data(),
                               host.labels.size() * sizeof(uint32_t)))
          << what << ", chunk " << i << ": labels differ";
    }
  }
}

std::vector<std::string> encode(const Mesh& mesh, uint32_t chunks, bool labelled) {
  std::vector<uint32_t> labels(mesh.num_vertices());
  for (uint32_t v = 0; v < labels.size(); ++v) labels[v] = (v * 7919u) % 5000u;
  wire::CodecOptions o;
  o.encode_speed = o.decode_speed = 10;  // the sequential coder, as fqpub and fqd write
  o.threads = 8;
  std::vector<std::string> out;
  EXPECT_TRUE(wire::encode_frame(mesh.view(), labelled ? labels.data() : nullptr, chunks, o, out).ok());
  return out;
}

TEST_F(CudaChunkDecode, EverySharedMeshAtEveryChunkCountReadsAsTheHostReads) {
  int meshes = 0;
  for (const char* file : kSharedMeshes) {
    const auto mesh = read_real_mesh(file);
    if (!mesh) continue;
    ++meshes;
    for (const uint32_t chunks : {1u, 2u, 7u, 64u, 256u}) {
      const bool labelled = chunks == 7 || chunks == 256;  // fqd's inputs have none, its results do
      const std::vector<std::string> bytes = encode(*mesh, chunks, labelled);
      for (const ChunkTeam team : kTeams)
        expect_device_reads_as_host(
            team, bytes, std::string(file) + " in " + std::to_string(chunks) + " chunks, " + team_name(team));
    }
  }
  if (meshes == 0) GTEST_SKIP() << "no shared mesh in " << mesh_dir();
}

/// Whether the host reader and the device take `chunk` alike (and read it alike when they do).
void expect_same_verdict(ChunkDecoder& dec, const std::string& chunk, int& taken, const std::string& what) {
  wire::detail::SequentialChunk host;
  const bool host_ok = wire::detail::read_sequential_chunk(chunk, wire::kMaxAttributeValue, host);
  const std::vector<std::string_view> one{chunk};
  const Status s = dec.decode(one, wire::kMaxAttributeValue);
  ASSERT_EQ(host_ok, s.ok()) << what << ": "
                             << (host_ok ? "the device refuses it: " + s.message()
                                         : std::string("the device takes it"));
  if (!host_ok) return;
  ++taken;
  std::vector<float> positions;
  std::vector<uint32_t> corners, labels;
  dec.download(positions, corners, labels);
  EXPECT_EQ(0, std::memcmp(positions.data(), host.positions.data(), host.positions.size() * sizeof(float)))
      << what;
  EXPECT_EQ(corners, host.corners) << what;
  EXPECT_EQ(labels, host.labels) << what;
}

TEST_F(CudaChunkDecode, DamagedChunksAreTakenAndReadAsTheHostReaderDoes) {
  std::mt19937 rng(35);
  std::vector<std::string> chunks;
  // uint8, uint16 and varint indices; with and without labels.
  for (const auto& [nx, ny] : {std::pair{8, 6}, std::pair{60, 40}, std::pair{300, 250}}) {
    const Mesh grid = test_wire::make_bumpy_grid(nx, ny);
    for (const bool labelled : {false, true})
      for (const std::string& c : encode(grid, 2, labelled)) chunks.push_back(c);
  }
  for (const ChunkTeam team : kTeams) {
    ChunkDecoder dec(team);
    int taken = 0;
    for (int trial = 0; trial < 1500; ++trial) {
      std::string bytes = chunks[size_t(trial) % chunks.size()];
      if (trial % 5 == 0) {
        bytes.resize(rng() % bytes.size());
      } else {
        for (int k = 0; k < 1 + trial % 3; ++k) {
          const size_t at = rng() % bytes.size();
          bytes[at] = static_cast<char>(bytes[at] ^ (1 << (rng() % 8)));
        }
      }
      expect_same_verdict(dec, bytes, taken, "trial " + std::to_string(trial));
    }
    std::printf("  %s: %d of 1500 damaged chunks taken by both\n", team_name(team).c_str(), taken);
  }
}

/// The position of the positions' wrap bounds in `chunk`: just past their symbols.
size_t bounds_at(const std::string& chunk) {
  wire::detail::SequentialPlan p;
  std::vector<uint32_t> ids;
  EXPECT_TRUE(wire::detail::plan_sequential_chunk(chunk, wire::kMaxAttributeValue, p, ids));
  wire::detail::ByteReader in{reinterpret_cast<const uint8_t*>(chunk.data()), chunk.size(), p.values_at + 3};
  std::vector<wire::detail::RansSymbol> room(wire::detail::rans_symbol_room(chunk.size(), 20));
  std::vector<uint32_t> buckets(wire::detail::kRansBuckets), out(3 * size_t(p.layout.points));
  EXPECT_EQ(wire::detail::decode_symbols(in, uint32_t(out.size()), 3,
                                         {room.data(), uint32_t(room.size()), buckets.data()}, out.data()),
            wire::detail::SymbolStatus::kOk);
  return in.pos;
}

TEST_F(CudaChunkDecode, BoundsNarrowerThanTheCorrectionsWrapAsDracoWraps) {
  // Corrections beyond the bounds (no encoder writes them, Draco's decoder takes them) leave
  // the warp's scan for Draco's own loop; both must still read as the host does.
  const std::string chunk = encode(test_wire::make_bumpy_grid(40, 30), 1, false)[0];
  const size_t at = bounds_at(chunk);
  int taken = 0;
  for (const auto& [lo, hi] : {std::pair{0, 3}, std::pair{-5, 5}, std::pair{100, 100},
                               std::pair{-2147483600, 2147483000}, std::pair{2147483000, 2147483647}}) {
    std::string bytes = chunk;
    std::memcpy(bytes.data() + at, &lo, 4);
    std::memcpy(bytes.data() + at + 4, &hi, 4);
    for (const ChunkTeam team : kTeams) {
      ChunkDecoder dec(team);
      expect_same_verdict(
          dec, bytes, taken,
          "bounds " + std::to_string(lo) + ".." + std::to_string(hi) + ", " + team_name(team));
    }
  }
  EXPECT_GE(taken, 12);
}

}  // namespace
}  // namespace fq::test
