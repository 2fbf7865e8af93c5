// A frame's sequential chunks decoded on the device: the compressed bytes go up, and the
// symbol decoding (Draco's schemes and rANS, wire/symbol_decode.h), the delta and wrap
// corrections, the dequantization and the widening of the connectivity run there, into device
// arrays at each chunk's offset. The host checks every chunk first (chunk_plan.h); what it
// decodes equals read_sequential_chunk's reading bit for bit (tests/cuda/cuda_chunk_decode_test.cpp).
// No CUDA types here: the device state is behind the pointer.
#pragma once

#include <cstdint>
#include <memory>
#include <string_view>
#include <vector>

#include "common/non_copyable.h"
#include "common/status.h"
#include "kernels/cuda/chunk_plan.h"

namespace fq::cuda {

/// Device times of one decode, from events on its stream (ms).
struct ChunkDecodeTimes {
  double upload_ms = 0;  ///< the packed bytes and the plans, host to device
  double kernel_ms = 0;  ///< the decode kernel
};

class ChunkDecoder : NonCopyable {
 public:
  explicit ChunkDecoder(ChunkTeam team = ChunkTeam::kBlock);
  ~ChunkDecoder();

  /// Plans `chunks` (plan_chunks, ids below `id_limit`), uploads them, decodes them on the
  /// device and waits for it. kInvalidInput naming the first chunk the host's checks or the
  /// device refuse, and why: such a frame is for the host codec. Buffers grow and are kept, so
  /// a stream of frames of about one size allocates nothing after the first.
  fq::Status decode(const std::vector<std::string_view>& chunks, uint32_t id_limit);

  /// The last decode's plan: each chunk's ids and its places in the device arrays.
  const ChunkPlan& plan() const;
  const ChunkDecodeTimes& times() const;

  /// The last decode's device arrays: 3 floats a point, 3 point indices a face (each chunk's
  /// own), a label a point (where its chunk is labelled); chunk after chunk (ChunkJob).
  const float* device_positions() const;
  const uint32_t* device_corners() const;
  const uint32_t* device_labels() const;

  /// The same arrays copied to the host.
  void download(std::vector<float>& positions, std::vector<uint32_t>& corners,
                std::vector<uint32_t>& labels) const;

 private:
  struct Device;
  std::unique_ptr<Device> d_;
};

/// Ok when a CUDA device is present; kUnavailable and why otherwise (the device tests and the
/// benchmark skip then).
fq::Status chunk_decoder_device();

}  // namespace fq::cuda
