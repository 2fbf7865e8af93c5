// fqbench --codec-device: the device decode of a frame's sequential chunks
// (kernels/cuda/chunk_decoder.h) against the host reader (read_sequential_chunk) on the same
// chunks, in one run: per frame and per chunk, for several chunk counts.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace fq::bench {

struct CodecDeviceBenchOptions {
  std::string mesh;  ///< a mesh file, or a name in mesh_dir
  std::string mesh_dir;
  std::vector<uint32_t> chunks;  ///< chunk counts; empty: fqpub's count for the mesh, 1, 16, 64, 256
  int host_threads = 16;         ///< the host reader's threads of the second column
  int repeat = 50;               ///< timed rounds; medians are reported
};

/// Runs the comparison and prints a Markdown table. Returns the exit code (3: no device).
int run_codec_device_bench(const CodecDeviceBenchOptions& o);

}  // namespace fq::bench
