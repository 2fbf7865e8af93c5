// Protobuf headers of the wire protocol: strict parsing and the mapping to fq::Params.
#pragma once

#include <cstdint>
#include <string_view>

#include "proto/fq.pb.h"
#include "proto/frame_codec.h"
#include "kernels/params.h"
#include "common/status.h"

namespace fq::wire {

/// The protocol version this build speaks; every header carries it.
inline constexpr uint32_t kWireVersion = 1;

/// Parses `bytes` into `out` and rejects anything this version does not fully understand:
/// unparsable bytes, unknown fields (at any depth) and enum values outside their enum.
/// Returns kInvalidInput with a message naming `what` (e.g. "frame header").
fq::Status parse_strict(std::string_view bytes, google::protobuf::Message& out, std::string_view what);

/// parse_strict plus the frame rules: version == kWireVersion, non-empty stream id,
/// 1 <= chunk_count <= kMaxChunks. kInvalidInput otherwise.
fq::Status parse_frame_header(std::string_view bytes, FrameHeader& out);

/// parse_strict plus version == kWireVersion and a non-empty stream id.
fq::Status parse_result_header(std::string_view bytes, ResultHeader& out);

/// parse_strict of a control request; kInvalidInput also when no request is set.
fq::Status parse_control_request(std::string_view bytes, ControlRequest& out);

/// parse_strict of a control reply.
fq::Status parse_control_reply(std::string_view bytes, ControlReply& out);

/// Copies every set field of `o` into `inout` (MODE_DEFAULT / METHOD_DEFAULT keep the current
/// method). Values are not range-checked here: call fq::validate on the result.
/// kInvalidArgument only for enum values outside their enum.
fq::Status apply_overrides(const ParamOverrides& o, fq::Params& inout);

/// Sets Params::filter / Params::cluster from `c`; COMPUTE_DEFAULT keeps them.
/// kInvalidArgument for values outside the enum.
fq::Status apply_compute(Compute c, fq::Params& inout);

/// What `p` computes, as the wire enum (FILTER when neither flag is set).
Compute compute_of(const fq::Params& p);

/// Every parameter of `p`, compute included.
void params_to_wire(const fq::Params& p, StreamParams& out);

/// Inverse of params_to_wire: every field of `w` replaces the one in `out` (MODE_DEFAULT,
/// METHOD_DEFAULT and COMPUTE_DEFAULT keep the current value). Values are not range-checked
/// here: call fq::validate. kInvalidArgument for enum values outside their enum.
fq::Status params_from_wire(const StreamParams& w, fq::Params& out);

/// The ParamOverrides that turn any Params into `p` (every field set).
void params_to_overrides(const fq::Params& p, ParamOverrides& out);

}  // namespace fq::wire
