// The periodic one-line stats log of each stream ([stats] interval_s), for operators who
// read logs rather than dashboards:
//   [stats] stream=cam0 fps=29.9 p99=31.2ms late=0 superseded=0 stale=0 errors=0
// fps, late, superseded, stale and errors are over the last interval; p99 is fqd's
// receive -> publish over the stream's last 2048 results. Each reason that lost the stream
// frames or results in the interval follows as a [drops] line saying what it means and what to
// change (drop_reasons.h).
#pragma once

#include <condition_variable>
#include <map>
#include <mutex>
#include <string>
#include <thread>

#include "common/non_copyable.h"
#include "daemon/stream/stream_registry.h"

namespace fq::daemon {

class StatsLog : NonCopyable {
 public:
  StatsLog(StreamRegistry& registry, double interval_s);
  ~StatsLog();

  /// Stops the thread (no final line); idempotent.
  void stop();

  /// The lines for one interval of `seconds`, given the counters at its start (replaced by
  /// the current ones, of the streams in `now` only): each stream's [stats] line, then its
  /// [drops] lines. Streams without a frame in the interval are left out.
  static std::vector<std::string> lines(const std::vector<StreamSnapshot>& now, double seconds,
                                        std::map<std::string, StreamCounters>& previous);

 private:
  void run();

  StreamRegistry& registry_;
  double interval_s_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace fq::daemon
