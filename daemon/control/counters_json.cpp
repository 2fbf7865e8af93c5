#include "daemon/control/counters_json.h"

namespace fq::daemon {

nlohmann::json counters_json(const wire::StreamCounters& c) {
  nlohmann::json stages = nlohmann::json::object();
  for (const wire::StagePercentiles& s : c.stages())
    stages[s.name()] = {{"p50_ms", s.p50_ms()}, {"p95_ms", s.p95_ms()}, {"p99_ms", s.p99_ms()}, {"count", s.count()}};
  return {{"stream", c.stream_id()},
          {"frames_in", c.frames_in()},
          {"frames_out", c.frames_out()},
          {"superseded", c.superseded()},
          {"dropped_stale", c.dropped_stale()},
          {"late", c.late()},
          {"errors", c.errors()},
          {"time_limited", c.time_limited()},
          {"subscriber_overflows", c.subscriber_overflows()},
          {"bad_send_time", c.bad_send_time()},
          {"temporal_resets", c.temporal_resets()},
          {"untracked", c.untracked()},
          {"preempted", c.preempted()},
          {"refused", c.refused()},
          {"memory_resets", c.memory_resets()},
          {"dropped_memory", c.dropped_memory()},
          {"stages", std::move(stages)}};
}

nlohmann::json counters_json(const wire::ControlReply& reply) {
  nlohmann::json streams = nlohmann::json::array();
  for (const wire::StreamCounters& c : reply.counters()) streams.push_back(counters_json(c));
  return {{"streams", std::move(streams)}};
}

}  // namespace fq::daemon
