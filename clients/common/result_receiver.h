// Consumer side of the wire protocol, shared by fqsub, fqstreambench, the tests and fq::client:
// receive [stream id][ResultHeader][chunks...], decode and check it.
#pragma once

#include <cstdint>
#include <string>
#include <vector>
#include <zmq.hpp>

#include "common/status.h"
#include "common/status_or.h"
#include "core/mesh_view.h"
#include "wire/fq.pb.h"

namespace fq::client {

struct ReceivedResult {
  std::string topic;
  wire::ResultHeader header;
  std::vector<zmq::message_t> chunks;
  int64_t receive_ns = 0;        ///< when this process got it
  Mesh mesh;                     ///< after decode_result (faces: see decode_result)
  std::vector<uint32_t> labels;  ///< after decode_result: the header's labels
};

/// Blocks for one published message into `out`: true for a valid result, false when the
/// socket's receive timeout expired first, an error for a message that is not a valid result
/// (`out` then keeps what could be read, so the caller can still count it by topic and header).
StatusOr<bool> receive_result(zmq::socket_t& sub, ReceivedResult& out);

/// True when receive_result's socket timed out (no message at all).
inline bool timed_out(const StatusOr<bool>& received) { return received.ok() && !*received; }

/// Decodes the chunks of an OK/LATE result (threads: chunks decoded at once). A POSITIONS
/// result carries no faces: they are `faces` (the input frame's triangles, 3 vertex ids
/// each) when given, else r.mesh has none. kInvalidInput when `faces` names a vertex the
/// result does not have.
Status decode_result(ReceivedResult& r, int threads = 1, const std::vector<uint32_t>* faces = nullptr);

/// The consumer's checks on a decoded result: vertex count as announced, finite
/// positions, every label below cluster_count, labels present iff cluster_count > 0.
Status check_result(const ReceivedResult& r);

/// Milliseconds from the producer's send time to this process's receive time.
double send_to_receive_ms(const ReceivedResult& r);

}  // namespace fq::client
