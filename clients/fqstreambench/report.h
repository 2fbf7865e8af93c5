// The benchmark's report: a readable summary, a Markdown table row for docs/BENCHMARKS.md,
// or JSON.
#pragma once

#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "clients/common/stream_stats.h"
#include "clients/fqstreambench/host_probe.h"
#include "wire/fq.pb.h"

namespace fq::bench {

/// fqd's host CPU over the measured run (in-process fqd only) and the floor it is set beside.
struct CpuInfo {
  bool measured = false;                              ///< false with --connect
  std::map<std::string, double> stage_seconds;        ///< fq_stage_cpu_seconds_total's deltas
  double threads_seconds = 0;                         ///< fq_cpu_seconds_total's delta
  double floor_decode_ms = -1, floor_encode_ms = -1;  ///< plain Draco on one frame's chunks
  double producers_ms = 0, collector_ms = 0;          ///< the benchmark's own threads, in total
};

struct RunInfo {
  std::string mesh_name;
  uint32_t vertices = 0, triangles = 0;
  std::string engine;
  int streams = 1;
  double fps = 0, seconds = 0, warmup = 0;
  uint32_t chunks = 1;
  std::string phases;  ///< "aligned" or "spread" (fqstreambench --phases)
  std::string compute;
  std::string result_form;                        ///< "positions" or "mesh" (fqd's setting for the streams)
  std::map<std::string, uint64_t> sent;           ///< all frames sent, per stream
  std::map<std::string, uint64_t> sent_measured;  ///< frames sent after the warm-up
  std::map<std::string, wire::StreamCounters> before, after;  ///< fqd's counters
  std::map<std::string, client::StreamStats> per_stream;
  client::StreamStats overall;
  CpuInfo cpu;
  HostQuiet host;  ///< over the sending
};

nlohmann::json report_json(const RunInfo& r);
/// Human-readable summary (several lines).
std::string report_text(const RunInfo& r);
/// "| mesh | V | streams x fps | chunks | engine | achieved fps | recv->pub p50/p95/p99 | ..." row.
std::string report_markdown_row(const RunInfo& r);
/// The header of the Markdown table report_markdown_row fills.
std::string report_markdown_header();

}  // namespace fq::bench
