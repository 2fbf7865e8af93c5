// What a consumer measures over the results it receives: counts, drops (sequence gaps),
// fps, and percentiles of receive->publish, send->receive and every stage.
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
  uint64_t drops() const { return drops_; }
  uint64_t late() const { return late_; }

  /// Results per second between the first and the last result.
  double fps() const;
  /// One status line: fps, latency p50/p99, drops, errors, and the last frame's estimated noise.
  std::string status_line() const;
  /// Everything, for --json and the benchmark reports.
  nlohmann::json to_json() const;

 private:
  uint64_t results_ = 0, errors_ = 0, bad_ = 0, drops_ = 0, late_ = 0;
  int64_t first_ns_ = 0, last_ns_ = 0;
  std::map<std::string, uint64_t> next_seq_;
  std::vector<double> latency_, send_to_receive_;
  std::map<std::string, std::vector<double>> stages_;
  float last_noise_ = 0.f;  ///< the last result's noise estimate (filter "qf+"), mean edges
};

}  // namespace fq::client
