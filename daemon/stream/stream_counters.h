// A stream's counters: what happened to its frames. Each counter is one row of
// FQ_STREAM_COUNTERS (Envoy's stats_macros.h: one list expanded into the struct and every
// surface): the StreamCounters member, the control socket's StreamCounters field and the key of
// the counters JSON are its name; /metrics shows it as its Prometheus family. Adding a counter
// is a row here, its increment site and its fq.proto field (docs/ARCHITECTURE.md).
#pragma once

#include <cstddef>
#include <cstdint>

namespace fq::daemon {

// Once the pipeline is idle,
//   frames_in == frames_out + errors + superseded + dropped_stale + preempted + refused
//                + dropped_memory.
// Notes beside the help texts:
// - subscriber_overflows: ZeroMQ skips a subscriber whose queue is full
//   (caps.max_subscriber_results) without telling until it has read half its queue, so one
//   overflow may stand for many missed results. Not part of the sum: the results were published.
// - bad_send_time: a producer clock an hour wrong or forged; such results stay out of the
//   send_to_publish histograms. Not part of the sum.
// - temporal_resets: frames of a stream filtered across frames (temporal > 0) that found under
//   half their vertices near the stream's last result. Not part of the sum.
// - preempted: stopped so that another stream's waiting frame meets its budget
//   (latency_policy.h); an error result is published, but not counted in errors.
// - preempted_others: the other side of preempted, counted on the stream whose waiting frame
//   a stop was for (the beneficiary), so that every stop says whom it served: over all
//   streams, sum(preempted_others) == sum(preempted). Not part of the sum.
// - memory_resets: what the stream keeps across frames (temporal history, cluster id track)
//   dropped to keep fqd within caps.memory_budget_mb (memory_account.h). Not part of the sum.
// - dropped_memory: frames that did not fit caps.memory_budget_mb once nothing else could go;
//   no result. Part of the sum.
// - ids_refused: track A looked at the frame (same triangles as the last) and refused its ids
//   (kernels/temporal_ids.h); the frame ran track B. Not part of the sum.
//
// COUNTER(name, Prometheus family, help); the help is /metrics' HELP line.
#define FQ_STREAM_COUNTERS(COUNTER)                                                                       \
  COUNTER(frames_in, "fq_frames_in_total", "Frames received (ingest messages attributed to the stream).") \
  COUNTER(frames_out, "fq_frames_out_total", "Results published with status OK or LATE.")                 \
  COUNTER(superseded, "fq_superseded_total",                                                              \
          "Frames replaced by a newer frame of their stream before an engine took them.")                 \
  COUNTER(dropped_stale, "fq_dropped_stale_total",                                                        \
          "Frames dropped because they were older than the budget when a worker was free.")               \
  COUNTER(late, "fq_late_total",                                                                          \
          "Results published after the stream's budget (also in fq_frames_out_total).")                   \
  COUNTER(errors, "fq_errors_total",                                                                      \
          "Error results published (bad input, invalid parameters, engine failure).")                     \
  COUNTER(time_limited, "fq_time_limited_total",                                                          \
          "Frames stopped at the engine time limit (also in fq_errors_total).")                           \
  COUNTER(subscriber_overflows, "fq_subscriber_overflows_total",                                          \
          "Times a subscriber's queue was full and it started missing results.")                          \
  COUNTER(bad_send_time, "fq_bad_send_time_total",                                                        \
          "Results whose producer send time was over an hour before publish or after it (left out of "    \
          "send_to_publish).")                                                                            \
  COUNTER(temporal_resets, "fq_temporal_resets_total",                                                    \
          "Scene cuts of a stream filtered across frames: its temporal history restarted.")               \
  COUNTER(untracked, "fq_untracked_total",                                                                \
          "Results published with the engine's cluster numbering because id tracking passed the time "    \
          "limit or fqd was stopping.")                                                                   \
  COUNTER(preempted, "fq_preempted_total",                                                                \
          "Frames stopped on the engine, unable to meet their budget, so that a lighter stream's frame "  \
          "could meet its own (not in fq_errors_total).")                                                 \
  COUNTER(preempted_others, "fq_preempted_others_total",                                                  \
          "Frames of other streams stopped on an engine so that a waiting frame of this stream, which "   \
          "would have missed its budget behind them, could meet it.")                                     \
  COUNTER(refused, "fq_refused_frames_total",                                                             \
          "Frames under the stream's id from a producer without CURVE that failed to decode: dropped "    \
          "unanswered, not errors (also in fq_refused_total{reason=\"undecodable\"}).")                   \
  COUNTER(memory_resets, "fq_memory_resets_total",                                                        \
          "Times the stream's temporal history or cluster id track was dropped to stay within "           \
          "caps.memory_budget_mb (its next frame ran alone).")                                            \
  COUNTER(dropped_memory, "fq_dropped_memory_total",                                                      \
          "Frames dropped without a result because they did not fit caps.memory_budget_mb once nothing "  \
          "else could be freed.")                                                                         \
  COUNTER(ids_refused, "fq_ids_refused_total",                                                            \
          "Frames of a stream filtered across frames that kept the last frame's triangles but whose "     \
          "vertex ids did not follow a smooth motion: filtered through the surface instead (track B).")

/// What happened to a stream's frames: a uint64_t member per row of FQ_STREAM_COUNTERS.
struct StreamCounters {
#define FQ_COUNTER_MEMBER(name, metric, help) uint64_t name = 0;
  FQ_STREAM_COUNTERS(FQ_COUNTER_MEMBER)
#undef FQ_COUNTER_MEMBER
};

/// A counter, as the pipeline names it where it counts (&StreamCounters::late).
using Counter = uint64_t StreamCounters::*;

/// One row of FQ_STREAM_COUNTERS as data, for the surfaces that walk it.
struct CounterRow {
  const char* name;    ///< member, wire field and JSON key
  const char* metric;  ///< Prometheus family
  const char* type;    ///< Prometheus type
  const char* help;
  Counter field;
};

inline constexpr CounterRow kCounterRows[] = {
#define FQ_COUNTER_ROW(name, metric, help) {#name, metric, "counter", help, &StreamCounters::name},
    FQ_STREAM_COUNTERS(FQ_COUNTER_ROW)
#undef FQ_COUNTER_ROW
};

}  // namespace fq::daemon
