#include "daemon/stream/metric_series.h"

namespace fq::daemon {

void MetricSeries::add(const MetricSeries& o) {
  for (const CounterRow& c : kCounterRows) counters.*c.field += o.counters.*c.field;
  for (const auto& [stage, h] : o.histograms) histograms[stage].add(h);
}

MetricSeries MetricSeries::since(const MetricSeries& base) const {
  MetricSeries d;
  for (const CounterRow& c : kCounterRows) d.counters.*c.field = counters.*c.field - base.counters.*c.field;
  for (const auto& [stage, h] : histograms) {
    const auto b = base.histograms.find(stage);
    d.histograms[stage] = b == base.histograms.end() ? h : h.since(b->second);
  }
  return d;
}

}  // namespace fq::daemon
