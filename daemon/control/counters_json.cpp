#include "daemon/control/counters_json.h"

#include "daemon/stream/stream_counters.h"

namespace fq::daemon {

nlohmann::json counters_json(const wire::StreamCounters& c) {
  nlohmann::json stages = nlohmann::json::object();
  for (const wire::StagePercentiles& s : c.stages())
    stages[s.name()] = {
        {"p50_ms", s.p50_ms()}, {"p95_ms", s.p95_ms()}, {"p99_ms", s.p99_ms()}, {"count", s.count()}};
  nlohmann::json j = {{"stream", c.stream_id()}, {"stages", std::move(stages)}};
#define FQ_COUNTER_TO_JSON(name, metric, help) j[#name] = c.name();
  FQ_STREAM_COUNTERS(FQ_COUNTER_TO_JSON)
#undef FQ_COUNTER_TO_JSON
  return j;
}

nlohmann::json counters_json(const wire::ControlReply& reply) {
  nlohmann::json streams = nlohmann::json::array();
  for (const wire::StreamCounters& c : reply.counters()) streams.push_back(counters_json(c));
  return {{"streams", std::move(streams)}};
}

}  // namespace fq::daemon
