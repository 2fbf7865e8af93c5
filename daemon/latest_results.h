// The latest published result of each stream, kept for the live viewer (GET
// /streams/ID/latest). Copying a result costs a memcpy of its Draco chunks (about 3 MB for
// igea), so a stream's results are kept only while someone has asked for them in the last
// kWatchSeconds; otherwise offer() returns at once.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "proto/fq.pb.h"

namespace fq::daemon {

struct LatestResult {
  uint64_t index = 0;  ///< 1 for the first result kept for the stream, then counting up
  wire::ResultHeader header;
  std::vector<std::string> chunks;  ///< as published: Draco meshes with fq_vid and fq_label
};

class LatestResults {
 public:
  static constexpr int kWatchSeconds = 10;

  /// Keeps a copy of an OK or LATE result when its stream is being watched (publisher thread).
  void offer(const wire::ResultHeader& header, const std::vector<std::string>& chunks);
  /// Marks the stream watched and waits up to `timeout` for a result with index > `after`;
  /// null when none came (or close() was called).
  std::shared_ptr<const LatestResult> wait_newer(const std::string& stream, uint64_t after,
                                                 std::chrono::milliseconds timeout);
  /// Wakes every waiter and makes later waits return at once (daemon stopping).
  void close();

 private:
  struct Entry {
    std::shared_ptr<const LatestResult> latest;
    uint64_t index = 0;
    std::chrono::steady_clock::time_point watched_until;
  };
  std::mutex mutex_;
  std::condition_variable changed_;
  std::map<std::string, Entry> streams_;
  bool closed_ = false;
};

}  // namespace fq::daemon
