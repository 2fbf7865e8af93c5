// A stream's counters: what happened to its frames. One field per Counter, listed once in
// kCounterFields, which the stream, the /metrics aggregate and the sums walk.
#pragma once

#include <cstddef>
#include <cstdint>

namespace fq::daemon {

/// What happened to a stream's frames. Once the pipeline is idle,
/// frames_in == frames_out + errors + superseded + dropped_stale + preempted + refused
/// + dropped_memory.
struct StreamCounters {
  uint64_t frames_in = 0;      ///< ingest messages attributed to the stream
  uint64_t frames_out = 0;     ///< results published with status OK or LATE
  uint64_t superseded = 0;     ///< replaced in the waiting slot by a newer frame
  uint64_t dropped_stale = 0;  ///< older than the budget when a worker was free
  uint64_t late = 0;           ///< published after the budget (also in frames_out)
  uint64_t errors = 0;         ///< error results published
  uint64_t time_limited = 0;   ///< stopped at caps.engine_time_limit_s (also in errors)
  /// Times a subscriber's queue was found full (caps.max_subscriber_results), so that it
  /// missed the result being published; ZeroMQ then skips that subscriber without telling
  /// until it has read half its queue, so one overflow may stand for many missed results.
  /// Not part of the sum above: the results were published.
  uint64_t subscriber_overflows = 0;
  /// Results whose producer send time was more than an hour before publish or after it (a
  /// wrong or forged clock): their send_to_publish is left out of the metrics, not folded
  /// into the histograms. Not part of the sum above.
  uint64_t bad_send_time = 0;
  /// Scene cuts of a stream filtered across frames (temporal > 0): frames that found under half
  /// their vertices near the stream's last result, so its history restarted. Not in the sum.
  uint64_t temporal_resets = 0;
  /// Results published with the engine's cluster numbering because id tracking was cut by
  /// the frame's time limit or the stop (also in frames_out).
  uint64_t untracked = 0;
  /// Frames stopped on the engine so that another stream's waiting frame meets its budget
  /// (latency_policy.h); an error result is published, but not counted in errors.
  uint64_t preempted = 0;
  /// Frames under the stream's id from a producer without CURVE that failed to decode: dropped
  /// unanswered (also in fq_refused_total{reason="undecodable"}), not errors; part of the sum.
  uint64_t refused = 0;
  /// Times what the stream keeps across frames (temporal history, cluster id track) was
  /// dropped to keep fqd within caps.memory_budget_mb; its next frame ran alone. Not in the sum.
  uint64_t memory_resets = 0;
  /// Frames dropped at admission or after decode because they did not fit caps.memory_budget_mb
  /// once nothing else could go (memory_account.h); no result. Part of the sum.
  uint64_t dropped_memory = 0;
};

enum class Counter {
  kIn,
  kOut,
  kSuperseded,
  kDroppedStale,
  kLate,
  kErrors,
  kTimeLimited,
  kSubscriberOverflows,
  kBadSendTime,
  kTemporalResets,
  kUntracked,
  kPreempted,
  kRefused,
  kMemoryResets,
  kDroppedMemory
};

/// The field of each Counter, in the enum's order.
inline constexpr uint64_t StreamCounters::*kCounterFields[] = {
    &StreamCounters::frames_in,     &StreamCounters::frames_out,
    &StreamCounters::superseded,    &StreamCounters::dropped_stale,
    &StreamCounters::late,          &StreamCounters::errors,
    &StreamCounters::time_limited,  &StreamCounters::subscriber_overflows,
    &StreamCounters::bad_send_time, &StreamCounters::temporal_resets,
    &StreamCounters::untracked,     &StreamCounters::preempted,
    &StreamCounters::refused,       &StreamCounters::memory_resets,
    &StreamCounters::dropped_memory};
static_assert(sizeof(kCounterFields) / sizeof(kCounterFields[0]) ==
                  static_cast<size_t>(Counter::kDroppedMemory) + 1,
              "one field per Counter");

}  // namespace fq::daemon
