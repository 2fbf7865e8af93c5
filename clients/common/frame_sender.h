// Producer side of the wire protocol, shared by fqpub, fqstreambench and the tests:
// a mesh becomes [stream id][FrameHeader][draco chunk]... on a PUSH socket.
#pragma once

#include <cstdint>
#include <string>
#include <vector>
#include <zmq.hpp>

#include "wire/fq.pb.h"
#include "wire/frame_codec.h"
#include "core/mesh_view.h"
#include "common/status.h"

namespace fq::client {

struct FrameSpec {
  std::string stream_id = "default";
  uint32_t chunks = 1;
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

/// Sends the parts as one multipart message (blocking while the socket's queue is full).
void send_parts(zmq::socket_t& push, const std::vector<std::string>& parts);

/// Wall-clock nanoseconds since the epoch (the clock of every *_time_ns field).
int64_t now_ns();

}  // namespace fq::client
