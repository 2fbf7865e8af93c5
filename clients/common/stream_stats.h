// What a consumer measures over the results it receives: counts, drops by reason, fps, and
// percentiles of receive->publish, send->receive and every stage.
//
// A consumer tells drop reasons apart only as far as the results say them: a frame stopped on
// fqd's engine comes as an error result naming why (preempted, time_limit, stopping), while a
// frame with no result at all is only a gap in the stream's sequence numbers (`gap`): fqd
// superseded it or dropped it stale, or this subscriber missed its result (its queue at fqd
// was full), or it never reached fqd. Which of these, only fqd's counters say (fqctl counters,
// fq_superseded_total, fq_dropped_stale_total, fq_subscriber_overflows_total).
#pragma once

#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "clients/common/result_receiver.h"

namespace fq::client {

class StreamStats {
 public:
  /// Accounts one received result; `ok` is false when it failed decoding or checks.
  void add(const ReceivedResult& r, bool ok);

  uint64_t results() const { return results_; }
  uint64_t errors() const { return errors_; }
  uint64_t bad() const { return bad_; }
  /// Frames without a good result: sequence gaps plus error results of a stopped frame.
  uint64_t drops() const;
  /// Drops by reason: "gap", "preempted", "time_limit", "stopping" (only those seen).
  const std::map<std::string, uint64_t>& drops_by_reason() const { return drops_by_reason_; }
  uint64_t late() const { return late_; }

  /// Results per second between the first and the last result.
  double fps() const;
  /// One status line: fps, latency p50/p99, drops (with each reason seen), errors, and the last
  /// frame's estimated noise.
  std::string status_line() const;
  /// Everything, for --json and the benchmark reports.
  nlohmann::json to_json() const;

 private:
  uint64_t results_ = 0, errors_ = 0, bad_ = 0, late_ = 0;
  std::map<std::string, uint64_t> drops_by_reason_;
  int64_t first_ns_ = 0, last_ns_ = 0;
  std::map<std::string, uint64_t> next_seq_;
  std::vector<double> latency_, send_to_receive_;
  std::map<std::string, std::vector<double>> stages_;
  float last_noise_ = 0.f;  ///< the last result's noise estimate (filter "qf+"), mean edges
};

}  // namespace fq::client
