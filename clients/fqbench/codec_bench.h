// fqbench --codec: the frame codec (encode_frame / decode_frame) against its floor, plain
// Draco on the same chunks with positions only, in one run on the same threads.
#pragma once

#include <cstdint>
#include <string>

namespace fq::bench {

struct CodecBenchOptions {
  std::string mesh;  ///< a mesh file, or a name in mesh_dir
  std::string mesh_dir;
  uint32_t chunks = 8;
  int threads = 2;  ///< codec threads (CodecOptions::threads) for ours and the floor
  int speed = 10;   ///< Draco encoding = decoding speed
  int position_bits = 16;
  int repeat = 20;  ///< timed rounds; medians are reported
  bool json = false;
};

/// Runs the comparison and prints a Markdown table (or one JSON object). Returns the exit code.
int run_codec_bench(const CodecBenchOptions& o);

}  // namespace fq::bench
