// One benchmark stream's producer: frames encoded before the run (so that producer CPU
// time does not compete with fqd during it), sent on its own PUSH socket at a fixed rate.
#pragma once

#include <atomic>
#include <cstdint>
#include <string>
#include <vector>
#include <zmq.hpp>

#include "clients/common/frame_sender.h"
#include "common/status.h"
#include "core/mesh_view.h"

namespace fq::bench {

struct ProducerOptions {
  client::FrameSpec spec;
  double fps = 30.0;
  double seconds = 10.0;
  double noise = 0.0;  ///< mean edges; each variant gets its own draw
  int variants = 4;    ///< distinct noisy frames cycled through (1 without noise)
  uint64_t seed = 1;
  double phase = 0.0;  ///< when in the frame period this stream sends, in periods: [0, 1)
};

class Producer {
 public:
  /// Encodes the frames of the run from `mesh`: during the run they are replayed (the same
  /// bytes under a new header), so the producers cost fqd's host almost nothing.
  Status prepare(const Mesh& mesh, const ProducerOptions& options);
  struct Sent {
    uint64_t all = 0;
    uint64_t measured = 0;  ///< sent at or after measure_from_ns
    double cpu_ms = 0;      ///< the sending thread's CPU time (re-stamping and sending)
  };
  /// Sends at the frame rate until the time is up or `stop`.
  Sent run(zmq::context_t& ctx, const std::string& endpoint, const std::atomic<bool>& stop,
           int64_t measure_from_ns);

  double encode_ms() const { return encode_ms_; }
  /// The mesh of frame `i` (its noise drawn as prepare drew it).
  Mesh frame_mesh(const Mesh& mesh, int i) const;

 private:
  ProducerOptions options_;
  std::vector<std::vector<std::string>> frames_;
  double encode_ms_ = 0.0;
};

}  // namespace fq::bench
