// What fqd does with one stream's frames: the filter/cluster parameters and compute mode,
// the latency budget and the output encoding. Defaults come from the config file; every
// key can be overridden per stream (config) and the parameters changed at run time.
#pragma once

#include <cstdint>
#include <string>

#include "common/status.h"
#include "core/param_table.h"
#include "core/params.h"
#include "wire/fq.pb.h"

namespace fq::daemon {

/// What a result carries (ResultForm on the wire). kPositions: the filtered positions only,
/// in frame vertex order, for consumers that have the input frame's faces; several times
/// cheaper to encode than kMesh, which also carries the connectivity (see docs/PROTOCOL.md).
enum class ResultForm { kPositions, kMesh };

/// How results are encoded on the publish socket.
struct OutputEncoding {
  ResultForm form = ResultForm::kPositions;
  int position_bits = 16;  ///< Draco position quantization; high enough not to undo smoothing
  uint32_t chunks = 0;     ///< result chunk count; 0 = same as the input frame
  int encode_speed = 10;   ///< Draco encoder speed 0..10 (10: sequential, fastest; 0: smallest)
  int decode_speed = 10;   ///< Draco decoder speed the encoder aims for, 0..10

  bool operator==(const OutputEncoding&) const = default;
};

/// ResultForm's names (the config's) and wire numbers.
inline constexpr ParamChoice kResultForms[] = {
    {"positions", static_cast<int>(ResultForm::kPositions), wire::POSITIONS},
    {"mesh", static_cast<int>(ResultForm::kMesh), wire::MESH}};

struct StreamSettings {
  Params params;             ///< params.filter / params.cluster are the compute mode
  double budget_ms = 100.0;  ///< receive -> publish budget; older frames are dropped, results flagged late
  OutputEncoding output;

  /// Parameters compared row by row of the parameter table (core/param_table.h).
  bool operator==(const StreamSettings& o) const {
    return same_params(params, o.params) && budget_ms == o.budget_ms && output == o.output;
  }
};

/// "filter" | "cluster" | "filter_and_cluster" into params.filter / params.cluster.
bool parse_compute(const std::string& s, Params& inout);
/// The name parse_compute accepts for the params' compute mode.
const char* compute_name(const Params& p);

/// "positions" | "mesh".
bool parse_result_form(const std::string& s, ResultForm& out);
const char* result_form_name(ResultForm f);
wire::ResultForm to_wire(ResultForm f);
ResultForm from_wire(wire::ResultForm f);

/// fq::validate (of the clustering parameters too, whatever the compute mode) plus the range
/// of every row of the stream setting table (daemon/config/stream_setting_table.h).
Status validate(const StreamSettings& s);

}  // namespace fq::daemon
