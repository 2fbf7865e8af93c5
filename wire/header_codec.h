// Protobuf headers of the wire protocol: strict parsing and the mapping to fq::Params.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

#include "common/status.h"
#include "core/param_table.h"
#include "core/params.h"
#include "wire/fq.pb.h"
#include "wire/frame_codec.h"

namespace fq::wire {

/// The protocol version this build speaks; every header and control message carries it.
/// Version 2: one parameter message (StreamParams gone), ResultStatus alone says LATE,
/// results in two forms (ResultForm) with labels in the header, versioned control messages.
inline constexpr uint32_t kWireVersion = 2;

/// Parses `bytes` into `out` and rejects anything this version does not fully understand:
/// unparsable bytes, unknown fields (at any depth) and enum values outside their enum.
/// Returns kInvalidInput with a message naming `what` (e.g. "frame header").
fq::Status parse_strict(std::string_view bytes, google::protobuf::Message& out, std::string_view what);

/// The messages below carry `version`, which is checked right after parsing (before unknown
/// fields, so a message of another version is refused naming both versions), then as
/// parse_strict. Frame headers also need a non-empty stream id and
/// 1 <= chunk_count <= kMaxChunks. kInvalidInput otherwise.
fq::Status parse_frame_header(std::string_view bytes, FrameHeader& out);

/// Also: a non-empty stream id, and labels either absent or one per vertex.
fq::Status parse_result_header(std::string_view bytes, ResultHeader& out);

/// Also kInvalidInput when no request is set.
fq::Status parse_control_request(std::string_view bytes, ControlRequest& out);

fq::Status parse_control_reply(std::string_view bytes, ControlReply& out);

/// Copies every set field of `o` into `inout` (MODE_DEFAULT / METHOD_DEFAULT keep the current
/// method). Values are not range-checked here: call fq::validate on the result.
/// kInvalidArgument only for enum values outside their enum; `inout` is then untouched.
fq::Status apply_overrides(const ParamOverrides& o, fq::Params& inout);

/// Sets Params::filter / Params::cluster from `c`; COMPUTE_DEFAULT keeps them.
/// kInvalidArgument for values outside the enum.
fq::Status apply_compute(Compute c, fq::Params& inout);

/// What `p` computes, as the wire enum (FILTER when neither flag is set).
Compute compute_of(const fq::Params& p);

/// "filter" | "cluster" | "filter_and_cluster": the compute modes' names in configs and on
/// command lines ("filter" for COMPUTE_DEFAULT).
const char* compute_name(Compute c);
/// The mode a name of compute_name stands for; nullopt for any other string.
std::optional<Compute> compute_from_name(std::string_view name);

/// The wire enum of each method and cluster geometry.
FilterMode to_wire(fq::FilterMethod m);
ClusterMethodWire to_wire(fq::ClusterMethod m);
ClusterGeometryWire to_wire(fq::ClusterGeometry g);

/// The field of a kWire row of the parameter table (core/param_table.h) in `o`, as the row's
/// Params value (an enum's native value); nullopt when unset or an enum's *_DEFAULT.
/// kInvalidArgument for an enum number outside the row's choices.
fq::Status wire_value(const fq::ParamRow& row, const ParamOverrides& o, std::optional<double>& out);
/// Sets the row's field of `o` to `value` (a Params value; an enum by its wire number).
void set_wire_value(const fq::ParamRow& row, double value, ParamOverrides& o);

/// Every filter and clustering parameter of `p`, each field set: the overrides that turn any
/// Params into `p` (apply_overrides is its inverse). The compute mode is compute_of(p).
void params_to_wire(const fq::Params& p, ParamOverrides& out);

}  // namespace fq::wire
