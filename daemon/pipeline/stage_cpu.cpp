#include "daemon/pipeline/stage_cpu.h"

#include <utility>

#include "common/pair_table.h"
#include "daemon/pipeline/prometheus_format.h"

namespace fq::daemon {
namespace {

constexpr std::pair<CpuStage, const char*> kStageNames[] = {
    {CpuStage::kIngest, "ingest"},      {CpuStage::kDecode, "decode"}, {CpuStage::kEngine, "engine"},
    {CpuStage::kTrackIds, "track_ids"}, {CpuStage::kEncode, "encode"}, {CpuStage::kPublish, "publish"}};
static_assert(std::size(kStageNames) == static_cast<size_t>(CpuStage::kCount), "one name per stage");

}  // namespace

const char* cpu_stage_name(CpuStage s) { return second_of(kStageNames, s).value_or("?"); }

std::string stage_cpu_metrics_text(const StageCpu& cpu, double threads_seconds) {
  std::string out;
  append_family(out, "fq_stage_cpu_seconds_total", "counter",
                "Host CPU time of each pipeline stage's work (ingest, decode, engine, track_ids, encode, "
                "publish), the shared pool's threads that helped it included; over fq_frames_out_total, "
                "the CPU a frame costs in that stage.");
  for (const auto& [stage, name] : kStageNames)
    out += std::string("fq_stage_cpu_seconds_total{stage=\"") + name + "\"} " +
           metric_number(cpu.seconds(stage)) + "\n";
  append_family(out, "fq_cpu_seconds_total", "counter",
                "Host CPU time of all of fqd's threads (stage threads, the shared pool, ZeroMQ I/O): the "
                "stages' sum plus queue hand-offs, socket I/O and housekeeping.");
  out += "fq_cpu_seconds_total " + metric_number(threads_seconds) + "\n";
  return out;
}

}  // namespace fq::daemon
