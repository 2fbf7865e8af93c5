#include "clients/common/result_receiver.h"

#include <cmath>
#include <zmq_addon.hpp>

#include "clients/common/frame_sender.h"
#include "wire/frame_codec.h"
#include "wire/header_codec.h"

namespace fq::client {

StatusOr<bool> receive_result(zmq::socket_t& sub, ReceivedResult& out) {
  std::vector<zmq::message_t> parts;
  if (!zmq::recv_multipart(sub, std::back_inserter(parts))) return false;
  out = ReceivedResult{};
  out.receive_ns = now_ns();
  if (parts.size() < 2)
    return invalid_input("published message has " + std::to_string(parts.size()) + " part(s)");
  out.topic = parts[0].to_string();
  const Status header =
      wire::parse_result_header(std::string_view(parts[1].data<char>(), parts[1].size()), out.header);
  for (size_t i = 2; i < parts.size(); ++i) out.chunks.push_back(std::move(parts[i]));
  FQ_RETURN_IF_ERROR(header);
  if (out.header.chunk_count() != out.chunks.size())
    return invalid_input("result header says " + std::to_string(out.header.chunk_count()) +
                         " chunk(s), message has " + std::to_string(out.chunks.size()));
  return true;
}

Status decode_result(ReceivedResult& r, int threads, const std::vector<uint32_t>* faces) {
  if (r.header.status() == wire::ERROR) return {};
  std::vector<std::string_view> views;
  for (const zmq::message_t& m : r.chunks) views.emplace_back(m.data<char>(), m.size());
  wire::CodecOptions opt;
  opt.threads = std::max(1, threads);
  r.labels.assign(r.header.labels().begin(), r.header.labels().end());
  if (r.header.form() == wire::MESH)
    return wire::decode_frame(views, r.header.vertex_count(), opt, r.mesh, nullptr);
  r.mesh = {};
  if (Status s = wire::decode_positions(views, r.header.vertex_count(), opt, r.mesh.positions); !s.ok())
    return s;
  if (faces == nullptr) return {};
  const uint32_t n = r.mesh.num_vertices();
  for (uint32_t v : *faces)
    if (v >= n)
      return invalid_input("the given faces use vertex " + std::to_string(v) + ", the result has " +
                           std::to_string(n) + " (faces of another mesh?)");
  r.mesh.triangles = *faces;
  return {};
}

Status check_result(const ReceivedResult& r) {
  const wire::ResultHeader& h = r.header;
  if (h.status() == wire::ERROR) return {};
  if (r.mesh.num_vertices() != h.vertex_count())
    return invalid_input("decoded " + std::to_string(r.mesh.num_vertices()) + " vertices, header says " +
                         std::to_string(h.vertex_count()));
  for (float v : r.mesh.positions)
    if (!std::isfinite(v)) return invalid_input("non-finite position in the result");
  if (h.cluster_count() > 0 && r.labels.size() != r.mesh.num_vertices())
    return invalid_input("result has " + std::to_string(h.cluster_count()) + " clusters but " +
                         std::to_string(r.labels.size()) + " labels for " +
                         std::to_string(r.mesh.num_vertices()) + " vertices");
  for (uint32_t l : r.labels)
    if (l >= h.cluster_count())
      return invalid_input("label " + std::to_string(l) + " out of range (" +
                           std::to_string(h.cluster_count()) + " clusters)");
  return {};
}

double send_to_receive_ms(const ReceivedResult& r) {
  return static_cast<double>(r.receive_ns - r.header.send_time_ns()) * 1e-6;
}

}  // namespace fq::client
