#include "clients/common/frame_sender.h"

#include <algorithm>
#include <chrono>
#include <zmq_addon.hpp>

#include "wire/header_codec.h"

namespace fq::client {

int64_t now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

uint32_t auto_chunks(uint32_t vertices) {
  const uint32_t wanted = (vertices + kAutoChunkVertices - 1) / kAutoChunkVertices;
  return std::clamp<uint32_t>(wanted, 1, kMaxAutoChunks);
}

Status build_frame(const MeshView& mesh, const FrameSpec& spec, uint64_t sequence,
                   std::vector<std::string>& parts) {
  std::vector<std::string> chunks;
  wire::CodecOptions opt;
  opt.position_bits = spec.position_bits;
  opt.encode_speed = spec.encode_speed;
  opt.decode_speed = spec.decode_speed;
  opt.threads = spec.encode_threads;
  const uint32_t count = spec.chunks == 0 ? auto_chunks(mesh.num_vertices) : spec.chunks;
  FQ_RETURN_IF_ERROR(wire::encode_frame(mesh, nullptr, count, opt, chunks));
  wire::FrameHeader h;
  h.set_version(wire::kWireVersion);
  h.set_stream_id(spec.stream_id);
  h.set_sequence(sequence);
  h.set_capture_time_ns(now_ns());
  h.set_send_time_ns(now_ns());
  *h.mutable_params() = spec.overrides;
  h.set_compute(spec.compute);
  h.set_chunk_count(static_cast<uint32_t>(chunks.size()));
  h.set_vertex_count(mesh.num_vertices);
  parts.clear();
  parts.push_back(spec.stream_id);
  parts.push_back(h.SerializeAsString());
  for (std::string& c : chunks) parts.push_back(std::move(c));
  return {};
}

int64_t restamp_frame(std::vector<std::string>& parts, uint64_t sequence) {
  wire::FrameHeader h;
  if (parts.size() < 2 || !h.ParseFromString(parts[1])) return 0;
  h.set_sequence(sequence);
  const int64_t now = now_ns();
  h.set_capture_time_ns(now);
  h.set_send_time_ns(now);
  parts[1] = h.SerializeAsString();
  return now;
}

bool send_parts(zmq::socket_t& push, const std::vector<std::string>& parts) {
  std::vector<zmq::const_buffer> buffers;
  buffers.reserve(parts.size());
  for (const std::string& p : parts) buffers.push_back(zmq::buffer(p));
  return zmq::send_multipart(push, buffers).has_value();
}

}  // namespace fq::client
