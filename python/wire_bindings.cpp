// The compiled parts of fq.wire (wrapped and documented in fq/wire.py): a frame as the
// multipart message fqd ingests, and a published message back to arrays, through fq_client's
// build_frame and decode_result, so Python frames are byte for byte what fqpub sends.
#include <pybind11/stl.h>

#include <string_view>

#include "python/bindings.h"
#include "python/client_frames.h"
#include "python/py_errors.h"
#include "wire/header_codec.h"

namespace fq::py {

namespace {

namespace pyb = pybind11;
using namespace pybind11::literals;

pyb::list encode_frame(const pyb::handle& v, const pyb::handle& f, const std::string& stream,
                       uint64_t sequence, uint32_t chunks, int position_bits, int encode_speed,
                       const std::string& compute, const pyb::dict& overrides) {
  const client::FrameSpec spec = frame_spec(stream, chunks, position_bits, encode_speed, compute, overrides);
  pyb::list out;
  for (const std::string& p : build_parts(v, f, spec, sequence)) out.append(pyb::bytes(p));
  return out;
}

// receive_result's checks on a message given as bytes instead of read from a socket.
pyb::dict decode_result(const std::vector<std::string>& parts) {
  if (parts.size() < 2)
    throw pyb::value_error("a result has at least 2 parts (stream id, header), got " +
                           std::to_string(parts.size()));
  client::ReceivedResult r;
  r.topic = parts[0];
  throw_if_error(wire::parse_result_header(parts[1], r.header));
  if (r.header.stream_id() != r.topic)
    throw pyb::value_error("part 0 is '" + r.topic + "' but the header's stream is '" + r.header.stream_id() +
                           "'");
  for (size_t i = 2; i < parts.size(); ++i) r.chunks.emplace_back(parts[i].data(), parts[i].size());
  if (r.header.chunk_count() != r.chunks.size())
    throw pyb::value_error("result header says " + std::to_string(r.header.chunk_count()) +
                           " chunk(s), message has " + std::to_string(r.chunks.size()));
  decode_checked(r);
  return result_dict(r);
}

}  // namespace

void bind_wire(pyb::module_& m) {
  m.def("encode_frame", &encode_frame, "V"_a, "F"_a, "stream"_a, "sequence"_a, "chunks"_a, "position_bits"_a,
        "encode_speed"_a, "compute"_a, "overrides"_a);
  m.def("decode_result", &decode_result, "parts"_a);
}

}  // namespace fq::py
