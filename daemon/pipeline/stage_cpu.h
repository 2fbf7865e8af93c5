// fqd's host CPU by stage: the thread CPU time of each stage's work, the pool threads that help
// it included (common/thread_cpu.h), summed over frames and streams since start. The rate of
// fq_stage_cpu_seconds_total{stage} over fq_frames_out_total is the CPU a frame costs in that
// stage; beside fq_cpu_seconds_total (all of fqd's threads) it says where a host's cores go.
// Written by the stage threads, read by /metrics and fqstreambench; lock-free.
#pragma once

#include <array>
#include <cstddef>
#include <string>

#include "common/thread_cpu.h"

namespace fq::daemon {

enum class CpuStage {
  kIngest,    ///< receive, header checks, admission (ingest thread)
  kDecode,    ///< decode, mesh checks, parameters (decode workers)
  kEngine,    ///< Engine::process: the CPU engine's work, or the CUDA engine's host side
  kTrackIds,  ///< stable cluster ids (encode workers)
  kEncode,    ///< result encode (encode workers)
  kPublish,   ///< result header, accounting, send (publisher thread)
  kCount
};

/// "ingest", "decode", "engine", "track_ids", "encode", "publish".
const char* cpu_stage_name(CpuStage s);

class StageCpu {
 public:
  /// The account a stage's work is charged to (with a CpuScope).
  CpuAccount& operator[](CpuStage s) { return accounts_[static_cast<size_t>(s)]; }
  double seconds(CpuStage s) const {
    return static_cast<double>(accounts_[static_cast<size_t>(s)].load(std::memory_order_relaxed)) * 1e-9;
  }

 private:
  std::array<CpuAccount, static_cast<size_t>(CpuStage::kCount)> accounts_{};
};

/// CPU seconds since start: each stage's, and all of fqd's threads' (daemon_threads.h).
struct CpuUsage {
  std::array<double, static_cast<size_t>(CpuStage::kCount)> stage_seconds{};
  double threads_seconds = 0;
};

/// fq_stage_cpu_seconds_total{stage} for every stage, and fq_cpu_seconds_total (`threads_seconds`,
/// all of fqd's threads), in the Prometheus text format.
std::string stage_cpu_metrics_text(const StageCpu& cpu, double threads_seconds);

}  // namespace fq::daemon
