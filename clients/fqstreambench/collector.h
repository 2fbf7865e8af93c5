// The benchmark's consumer: one SUB socket receiving every stream's results, keeping the
// statistics of results whose frames were sent after the warm-up.
#pragma once

#include <atomic>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <zmq.hpp>

#include "clients/common/stream_stats.h"
#include "common/status.h"
#include "core/mesh_view.h"

namespace fq::bench {

class Collector {
 public:
  /// Connects to `publish` and returns once results reach it: probe frames (stream
  /// "__probe") are pushed to `ingest` until one comes back.
  Status connect(zmq::context_t& ctx, const std::string& publish, const std::string& ingest);

  /// Receives until `stop`; results of frames sent at or after `measure_from_ns` count.
  /// Returns the receiving thread's CPU ms.
  double run(const std::atomic<bool>& stop, int64_t measure_from_ns, bool decode);

  /// Results received per stream (warm-up included), for draining.
  uint64_t received(const std::string& stream) const;
  std::map<std::string, client::StreamStats> per_stream() const;
  client::StreamStats overall() const;

 private:
  zmq::socket_t sub_;
  mutable std::mutex mutex_;
  std::map<std::string, uint64_t> received_;
  std::map<std::string, client::StreamStats> stats_;
  client::StreamStats overall_;
};

}  // namespace fq::bench
