#include "daemon/ingest.h"

#include <spdlog/spdlog.h>

#include <zmq_addon.hpp>

#include "proto/frame_codec.h"
#include "proto/header_codec.h"

namespace fq::daemon {
namespace {

Status check_framing(const std::vector<zmq::message_t>& parts, const Caps& caps) {
  if (parts.size() < 3)
    return invalid_input("expected [stream id][FrameHeader][draco chunk]..., got " +
                         std::to_string(parts.size()) + " part(s)");
  uint64_t bytes = 0;
  for (const zmq::message_t& m : parts) bytes += m.size();
  if (bytes > caps.max_frame_bytes)
    return invalid_input("frame of " + std::to_string(bytes) + " bytes is over the cap of " +
                         std::to_string(caps.max_frame_bytes));
  return {};
}

Status check_header(const wire::FrameHeader& h, const std::string& topic, size_t chunk_parts,
                    const Caps& caps) {
  if (h.stream_id() != topic)
    return invalid_input("header stream id '" + h.stream_id() + "' does not match the topic '" + topic + "'");
  if (h.chunk_count() != chunk_parts)
    return invalid_input("header says " + std::to_string(h.chunk_count()) + " chunk(s), message has " +
                         std::to_string(chunk_parts));
  if (h.vertex_count() > caps.max_vertices)
    return invalid_input("frame has " + std::to_string(h.vertex_count()) + " vertices, over the cap of " +
                         std::to_string(caps.max_vertices));
  return {};
}

}  // namespace

FramePtr admit_message(std::vector<zmq::message_t>& parts, Pipeline& p) {
  auto f = std::make_unique<FrameJob>();
  f->receive_ns = wall_ns();
  f->stream_id = parts.empty() ? std::string() : parts[0].to_string();
  f->arrival = p.arrivals[f->stream_id]++;
  if (!p.registry.settings(f->stream_id, f->settings)) {
    f->error = invalid_input(
        "too many streams (caps.max_streams = " + std::to_string(p.config.caps.max_streams) + ")");
    return f;
  }
  p.registry.count(f->stream_id, Counter::kIn);
  Status s = check_framing(parts, p.config.caps);
  if (s.ok())
    s = wire::parse_frame_header(std::string_view(parts[1].data<char>(), parts[1].size()), f->header);
  if (s.ok()) s = check_header(f->header, f->stream_id, parts.size() - 2, p.config.caps);
  if (!s.ok()) {
    f->error = s;
    return f;
  }
  for (size_t i = 2; i < parts.size(); ++i) f->chunks.push_back(std::move(parts[i]));
  return f;
}

void run_ingest(zmq::socket_t socket, Pipeline& p) {
  std::vector<zmq::message_t> parts;
  for (;;) {
    parts.clear();
    try {
      if (!zmq::recv_multipart(socket, std::back_inserter(parts))) continue;
    } catch (const zmq::error_t& e) {
      if (e.num() == ETERM) break;
      spdlog::error("ingest: {}", e.what());
      continue;
    }
    FramePtr f = admit_message(parts, p);
    if (!f->error.ok()) {
      const Status why = f->error;
      p.fail(std::move(f), why);
    } else {
      p.note_queued(*f);
      p.decode_queue.push(std::move(f));
    }
  }
  socket.close();
}

}  // namespace fq::daemon
