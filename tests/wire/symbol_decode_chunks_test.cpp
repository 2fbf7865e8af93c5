// wire/symbol_decode.h against draco::DecodeSymbols on the symbols of real chunks: every
// shared mesh, cut into chunks by the frame codec's writer (positions and labels), each
// chunk's symbol streams decoded by both.
#include <gtest/gtest.h>

#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "tests/support/shared_meshes.h"
#include "tests/wire/symbol_decoders.h"
#include "wire/frame_codec.h"
#include "wire/sequential_layout.h"
#include "wire/sequential_values.h"

namespace fq::test_wire {
namespace {

using wire::detail::ByteReader;

/// The scheme of the stream at `in` as a word: "tagged" or "raw, N-bit symbols".
std::string scheme_of(const ByteReader& in) {
  if (in.remaining() < 2) return "short";
  return in.data[in.pos] == 0 ? "tagged" : "raw, " + std::to_string(in.data[in.pos + 1]) + "-bit symbols";
}

/// Both decoders on every symbol stream of `chunk`; counts the streams by scheme.
void compare_chunk_streams(const std::string& chunk, SymbolRoom& room, std::map<std::string, int>& schemes,
                           const std::string& what) {
  wire::detail::SequentialLayout l;
  std::vector<uint8_t> runs;
  size_t corners_end = 0, values_at = 0;
  ASSERT_TRUE(wire::detail::read_sequential_layout(chunk, l, runs)) << what;
  ASSERT_TRUE(wire::detail::sequential_corners_end(chunk, l, corners_end)) << what;
  ASSERT_TRUE(wire::detail::read_attribute_specs(chunk, corners_end, l.labelled, values_at)) << what;
  ByteReader in{reinterpret_cast<const uint8_t*>(chunk.data()), chunk.size(), values_at};
  for (const uint32_t components : {3u, 1u}) {
    if (components == 1 && !l.labelled) break;
    wire::detail::WrapBounds bounds;
    ASSERT_TRUE(wire::detail::read_delta_head(in)) << what;
    ++schemes[std::string(components == 3 ? "positions, " : "labels, ") + scheme_of(in)];
    bool took = false;
    size_t end = 0;
    EXPECT_EQ("", compare_symbol_readings(in.data, in.size, in.pos, l.points * components, components, room,
                                          &took, &end))
        << what;
    ASSERT_TRUE(took) << what;
    in.pos = end;
    ASSERT_TRUE(wire::detail::read_wrap_bounds(in, bounds)) << what;
  }
}

TEST(SymbolDecodeChunks, RealChunksDecodeAsDracoDecodesThem) {
  SymbolRoom room;
  std::map<std::string, int> schemes;
  int meshes = 0;
  for (const char* file : test::kSharedMeshes) {
    const auto mesh = test::read_real_mesh(file);
    if (!mesh) continue;
    ++meshes;
    std::vector<uint32_t> labels(mesh->num_vertices());
    for (uint32_t v = 0; v < labels.size(); ++v) labels[v] = (v * 7919u) % 5000u;
    wire::CodecOptions o;
    o.encode_speed = o.decode_speed = 10;  // Draco's sequential coder, as fqpub and fqd write
    o.threads = 2;
    for (const uint32_t chunks : {1u, 9u, 64u}) {
      std::vector<std::string> out;
      ASSERT_TRUE(wire::encode_frame(mesh->view(), labels.data(), chunks, o, out).ok()) << file;
      for (size_t i = 0; i < out.size(); ++i)
        compare_chunk_streams(
            out[i], room, schemes,
            std::string(file) + ", chunk " + std::to_string(i) + " of " + std::to_string(chunks));
    }
  }
  if (meshes == 0) GTEST_SKIP() << "no shared mesh in " << test::mesh_dir();
  for (const auto& [scheme, count] : schemes) std::printf("  %5d streams %s\n", count, scheme.c_str());
}

}  // namespace
}  // namespace fq::test_wire
