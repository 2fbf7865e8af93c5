// Producer side of the wire protocol, shared by fqpub, fqstreambench, the tests and the
// installed client library (fq::client): a mesh becomes [stream id][FrameHeader][draco
// chunk]... on a PUSH socket.
#pragma once

#include <cstdint>
#include <string>
#include <vector>
#include <zmq.hpp>

#include "common/status.h"
#include "core/mesh_view.h"
#include "wire/fq.pb.h"
#include "wire/frame_codec.h"

namespace fq::client {

/// Vertices a chunk gets when the producer leaves the count to build_frame (FrameSpec::chunks
/// = 0): about 2 ms of Draco decoding on one core of an H100 host (igea's 134K vertices decoded
/// in 16-18 ms as one chunk), and fqd decodes a frame's chunks at once, so a frame's decode
/// takes about that long when cores are free (igea 1 x 30: p50 21-23 ms with one chunk,
/// 7.6-8.2 with eight; docs/BENCHMARKS.md). Chunks cost a little in bytes (igea: +0.6 % from 8
/// to 16 chunks).
constexpr uint32_t kAutoChunkVertices = 16384;
/// At most this many chunks are chosen (a frame's decode is spread over at most this many cores).
constexpr uint32_t kMaxAutoChunks = 16;

/// The chunks build_frame makes of a frame of `vertices` vertices when FrameSpec::chunks is 0.
uint32_t auto_chunks(uint32_t vertices);

struct FrameSpec {
  std::string stream_id = "default";
  uint32_t chunks = 1;  ///< Draco chunks per frame; 0: auto_chunks of the frame's vertex count
  int position_bits = 16;
  int encode_speed = 10;  ///< Draco encoder speed 0..10 (10: fastest to encode and decode)
  int decode_speed = 10;
  int encode_threads = 1;
  wire::ParamOverrides overrides;  ///< per-frame parameter overrides (unset = stream's)
  wire::Compute compute = wire::COMPUTE_DEFAULT;
};

/// The message parts of one frame: topic, header (send_time_ns stamped now), chunks.
Status build_frame(const MeshView& mesh, const FrameSpec& spec, uint64_t sequence,
                   std::vector<std::string>& parts);

/// Makes an already built frame (build_frame's parts) frame number `sequence`, captured and
/// sent now, so encoded frames can be sent again without encoding. Returns the new send time
/// (now_ns), or 0 when parts[1] is not a frame header (then the parts are left unchanged).
int64_t restamp_frame(std::vector<std::string>& parts, uint64_t sequence);

/// Sends the parts as one multipart message (blocking while the socket's queue is full or no
/// fqd is connected); false when the socket's send timeout (ZMQ_SNDTIMEO) passed first.
bool send_parts(zmq::socket_t& push, const std::vector<std::string>& parts);

/// Wall-clock nanoseconds since the epoch (the clock of every *_time_ns field).
int64_t now_ns();

}  // namespace fq::client
