// One host memory budget (caps.memory_budget_mb) for what fqd keeps per stream: its temporal
// history (stream_history.h), its cluster id track (label_tracks.h), the /latest copy for the
// viewer (latest_results.h) and its frames queued or in flight (from admission to publish).
// Each was bounded apart or not at all, so 64 streams of 1M-vertex frames with temporal
// filtering could hold more than the host has. Every holder charges the bytes it keeps here
// (estimated from vertex and face counts and element sizes) and credits them when it frees
// them; a charge that would pass the budget first makes room, in this order (the shedder the
// pipeline installs, memory_shed.h):
//   1. the /latest copies of streams nobody watches now;
//   2. what the stream that least recently had a frame keeps across frames (its temporal
//      history and cluster id track; its next frame runs alone, as after a restart), counted
//      `memory_resets` on that stream, then the next such stream, never the charging one;
//   3. nothing more: the charge fails. A new frame is then dropped, counted `dropped_memory`;
//      a history or track that does not fit is dropped (counted `memory_resets`); a /latest
//      copy is not kept (it makes room by step 1 only: the viewer keeps its last result).
// Thread-safe; the shedder runs without this object's lock, so it may credit.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <mutex>

namespace fq::daemon {

enum class MemoryKind { kHistory, kLabelTrack, kLatest, kQueued, kCount };

/// The `kind` label of fq_memory_bytes.
const char* memory_kind_name(MemoryKind k);

/// How far a charge may make room (the steps above).
enum class Shed { kNone, kIdleLatest, kHistories };

class MemoryAccount {
 public:
  /// Frees, in the order above and as far as `upto`, until `need` more bytes fit or nothing
  /// more may go; never what `keep` (the charging stream, may be null) holds.
  using Shedder = std::function<void(uint64_t need, Shed upto, const void* keep)>;

  /// 0: unbounded (no charge fails, nothing is shed).
  void set_budget(uint64_t bytes);
  uint64_t budget() const;
  /// Installed by the pipeline before frames flow, removed (empty) before it goes.
  void set_shedder(Shedder shedder);

  /// Adds `bytes` of `kind` when the total then stays within the budget, making room first
  /// as far as `upto`; false (nothing added) when it cannot.
  bool charge(MemoryKind kind, uint64_t bytes, Shed upto, const void* keep);
  void credit(MemoryKind kind, uint64_t bytes);

  uint64_t bytes(MemoryKind kind) const;
  uint64_t total() const;
  /// The highest total since start: never above the budget while it was unchanged.
  uint64_t peak() const;

 private:
  bool try_add(MemoryKind kind, uint64_t bytes);  // takes mutex_

  mutable std::mutex mutex_;  ///< the members below
  std::array<uint64_t, static_cast<size_t>(MemoryKind::kCount)> bytes_{};
  uint64_t total_ = 0;
  uint64_t peak_ = 0;
  uint64_t budget_ = 0;
  Shedder shedder_;
};

/// What one holder has charged, credited when it is released, replaced or destroyed. Its
/// holder's lock guards it; a holder that charges before taking its lock moves it in after.
class MemoryCharge {
 public:
  MemoryCharge() = default;
  MemoryCharge(const MemoryCharge&) = delete;
  MemoryCharge& operator=(const MemoryCharge&) = delete;
  MemoryCharge(MemoryCharge&& o) noexcept;
  MemoryCharge& operator=(MemoryCharge&& o) noexcept;
  ~MemoryCharge() { release(); }

  /// Holds `bytes` of `kind` on `account` (null: nothing is counted, always true) in place of
  /// what it held: less is credited at once; more is charged (MemoryAccount::charge). False
  /// when that failed: it still holds what it held, and the holder drops what it keeps.
  bool set(MemoryAccount* account, MemoryKind kind, uint64_t bytes, Shed upto, const void* keep);
  void release();
  uint64_t bytes() const { return bytes_; }

 private:
  MemoryAccount* account_ = nullptr;
  MemoryKind kind_ = MemoryKind::kQueued;
  uint64_t bytes_ = 0;
};

}  // namespace fq::daemon
