// The per-stream counters (FQ_STREAM_COUNTERS, daemon/stream/stream_counters.h) against their
// surfaces: fq.proto's StreamCounters by protobuf reflection (a field per row, a row per
// counter field), and each counter, counted on a stream, through the control socket's
// get_counters, the counters JSON and the Prometheus text.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "daemon/control/control_server.h"
#include "daemon/control/counters_json.h"
#include "daemon/control/prometheus_text.h"
#include "daemon/stream/frame_job.h"

namespace fq::daemon {
namespace {

namespace pb = google::protobuf;

TEST(StreamCounters, EveryRowHasItsWireFieldAndEveryCounterFieldARow) {
  const pb::Descriptor* d = wire::StreamCounters::descriptor();
  std::set<std::string> rows, metrics;
  for (const CounterRow& row : kCounterRows) {
    EXPECT_TRUE(rows.insert(row.name).second) << row.name;
    EXPECT_TRUE(metrics.insert(row.metric).second) << row.metric;
    EXPECT_EQ(std::string(row.type), "counter") << row.name;
    EXPECT_TRUE(std::string(row.metric).ends_with("_total")) << row.metric;
    const pb::FieldDescriptor* f = d->FindFieldByName(row.name);
    ASSERT_NE(f, nullptr) << "StreamCounters has no field " << row.name;
    EXPECT_EQ(f->cpp_type(), pb::FieldDescriptor::CPPTYPE_UINT64) << row.name;
  }
  // The stream's id and its stage percentiles are not counters.
  for (int i = 0; i < d->field_count(); ++i)
    if (d->field(i)->cpp_type() == pb::FieldDescriptor::CPPTYPE_UINT64)
      EXPECT_TRUE(rows.count(d->field(i)->name()))
          << "StreamCounters." << d->field(i)->name() << " has no row";
}

TEST(StreamCounters, EachCounterReachesEverySurface) {
  DaemonConfig c;
  StreamRegistry registry(c);
  const int64_t now = wall_ns();
  StreamPtr s = registry.admit("cam0", now);
  ASSERT_NE(s, nullptr);
  // A different count per counter, so that a surface that shows one counter's value under
  // another's name fails.
  uint64_t n = 0;
  for (const CounterRow& row : kCounterRows) s->count(row.field, ++n + 100);

  wire::ControlRequest q;
  q.mutable_get_counters()->set_stream_id("cam0");
  const wire::ControlReply reply = handle_control(q, registry, c.caps);
  ASSERT_TRUE(reply.ok()) << reply.error();
  ASSERT_EQ(reply.counters_size(), 1);
  const wire::StreamCounters& w = reply.counters(0);
  const nlohmann::json j = counters_json(w);

  MetricsInput in;
  registry.metric_series(now, 0, in.series, in.other);
  const std::string text = prometheus_text(in);

  n = 0;
  for (const CounterRow& row : kCounterRows) {
    const uint64_t want = ++n + 100;
    EXPECT_EQ(w.GetReflection()->GetUInt64(w, w.GetDescriptor()->FindFieldByName(row.name)), want)
        << row.name;
    EXPECT_EQ(j.value(row.name, uint64_t{0}), want) << row.name;
    EXPECT_NE(text.find(std::string("# HELP ") + row.metric + " " + row.help + "\n# TYPE " + row.metric +
                        " counter\n"),
              std::string::npos)
        << row.metric;
    EXPECT_NE(text.find(std::string(row.metric) + "{stream=\"cam0\"} " + std::to_string(want) + "\n"),
              std::string::npos)
        << row.metric;
  }
}

}  // namespace
}  // namespace fq::daemon
