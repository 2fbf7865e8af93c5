// What /metrics shows of streams: the counters and latency histograms of a stream, or of many
// summed. A stream has series of its own only while it is configured or has had a frame within
// caps.metric_series_idle_s; every other stream's counts move into one series labelled
// stream="other", so that ids that come and go (junk, a farm of short-lived cameras) cost a
// monitoring system no new series, and the sums over streams never go down.
#pragma once

#include <map>
#include <string>

#include "daemon/stream/latency_histogram.h"
#include "daemon/stream/stream_counters.h"

namespace fq::daemon {

/// The label value of the aggregate series.
inline constexpr const char* kOtherStreams = "other";

struct MetricSeries {
  StreamCounters counters;
  std::map<std::string, LatencyHistogram> histograms;  ///< by stage

  /// Adds `o`'s counts.
  void add(const MetricSeries& o);
  /// The counts since `base`, an earlier copy of this series.
  MetricSeries since(const MetricSeries& base) const;
};

/// A stream's series as /metrics shows them.
struct NamedSeries {
  std::string stream_id;
  MetricSeries series;
};

}  // namespace fq::daemon
