// What fq.wire, fq.Producer and fq.Consumer share: a FrameSpec from Python's keywords and a
// received result as the dict fq/wire.py turns into a Result. The codec itself is fq_wire's
// and fq_client's (build_frame, decode_result): nothing here encodes or decodes Draco.
#pragma once

#include <pybind11/pybind11.h>

#include <optional>
#include <string>
#include <vector>

#include "clients/common/frame_sender.h"
#include "clients/common/result_receiver.h"

namespace fq::py {

/// fqpub's choices for a frame: chunks (0: by the frame's size, as fqpub), position bits,
/// Draco speed (encode = decode, as fqpub), compute ("" = the stream's) and parameter
/// overrides (ParamOverrides field name -> value, checked as fqpub checks --sigma-s ...).
/// ValueError for a bad value, TypeError for a name that is not a wire parameter.
client::FrameSpec frame_spec(const std::string& stream, uint32_t chunks, int position_bits, int encode_speed,
                             const std::string& compute, const pybind11::dict& overrides);

/// The message parts of frame `sequence` (build_frame, with the GIL released) of V and F as
/// to_mesh takes them; ValueError for bad arrays or a mesh the codec refuses.
std::vector<std::string> build_parts(const pybind11::handle& v, const pybind11::handle& f,
                                     const client::FrameSpec& spec, uint64_t sequence);

/// Decodes and checks a received result with the GIL released; ValueError when it is not a
/// valid result. An ERROR result decodes to no positions.
void decode_checked(client::ReceivedResult& r);

/// {"positions", "labels", "faces", "header"} of a decoded result: positions (n, 3) float32,
/// labels uint32 or None, faces (m, 3) for a MESH result or None, the header as a dict.
pybind11::dict result_dict(const client::ReceivedResult& r);

/// Every field of a ResultHeader by its name (enums by their names, timings as name -> ms),
/// labels left out (result_dict carries them as an array).
pybind11::dict header_dict(const wire::ResultHeader& h);

}  // namespace fq::py
