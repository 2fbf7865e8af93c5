// The /metrics families about fqd as a service rather than about its streams' frames: build
// info, refusals on the ZeroMQ doors by reason, SUB producers connected again, each stream's
// budget, engine busy time, queue depths and the process (CPU, memory, file descriptors). They
// are what alert rules and the dashboard in deploy/monitoring read (docs/DAEMON.md has PromQL
// for each).
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "daemon/pipeline/process_stats.h"

namespace fq::daemon {

struct EngineLoad {
  std::string name;  ///< "cpu", "cuda:0 NVIDIA H100 ..."
  double busy_seconds = 0;
  uint64_t frames = 0;
};

struct ServiceMetricsInput {
  std::vector<std::pair<std::string, uint64_t>> refusals;  ///< every reason, zeros included
  std::vector<std::pair<std::string, double>> budgets_ms;  ///< stream id, budget
  std::vector<EngineLoad> engines;                         ///< in engine order (label index)
  std::vector<std::pair<std::string, size_t>> queues;      ///< queue name, items waiting
  uint64_t ingest_reconnects = 0;                          ///< SUB producers connected again
  std::vector<std::pair<std::string, uint64_t>> memory;    ///< kind, bytes charged (memory_account.h)
  uint64_t memory_peak = 0;                                ///< the highest total charged since start
  uint64_t memory_budget = 0;                              ///< caps.memory_budget_mb in bytes; 0 = unbounded
  ProcessStats process;
};

/// The families in the Prometheus text format.
std::string service_metrics_text(const ServiceMetricsInput& in);

}  // namespace fq::daemon
