// The latest published result of each stream, kept for the live viewer (GET
// /streams/ID/latest): what a browser needs to draw it. A POSITIONS result's chunks carry no
// faces, so the input frame's triangles are kept beside them; a stream's faces repeat frame
// after frame, so they are kept once and shared (with an id the viewer can cache them by)
// until they change. Copying a result costs a memcpy of its chunks (about 0.5 MB for igea in
// the POSITIONS form, 3 MB as a MESH), so a stream's results are kept only while someone has
// asked for them in the last kWatchSeconds; otherwise offer() returns at once. What is kept
// for a stream lives in its Stream (stream.h, under this object's lock) and goes with it. A
// copy is charged to the host memory budget (memory_account.h): copies of streams nobody
// watches now are the first thing it drops, and a copy that does not fit is not kept.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "daemon/stream/stream.h"
#include "wire/fq.pb.h"

namespace fq::daemon {

struct LatestResult {
  uint64_t index = 0;               ///< 1 for the first result kept for the stream, then counting up
  wire::ResultHeader header;        ///< as published: form, labels, counts
  std::vector<std::string> chunks;  ///< as published: Draco point clouds (POSITIONS) or meshes (MESH)
  /// POSITIONS: the input frame's triangles (3 vertex ids each); null for MESH.
  std::shared_ptr<const std::vector<uint32_t>> faces;
  uint64_t faces_id = 0;  ///< changes exactly when `faces` change (0 for MESH)
};

class StreamRegistry;

class LatestResults {
 public:
  static constexpr int kWatchSeconds = 10;

  explicit LatestResults(const StreamRegistry& registry) : registry_(registry) {}

  /// Keeps a copy of an OK or LATE result of `stream` when it is being watched (publisher
  /// thread). `triangles` are the input frame's (kept for POSITIONS results only).
  void offer(Stream& stream, const wire::ResultHeader& header, const std::vector<std::string>& chunks,
             const std::vector<uint32_t>& triangles);
  /// Marks the stream watched and waits up to `timeout` for a result with index > `after`;
  /// null when none came, when the stream is not registered, or once close() was called.
  std::shared_ptr<const LatestResult> wait_newer(const std::string& stream, uint64_t after,
                                                 std::chrono::milliseconds timeout);
  /// The memory budget's first step: drops the copies of streams not watched now (the ones
  /// watched longest ago first) until `need` bytes are freed, never `keep`'s; the bytes freed.
  uint64_t drop_idle(uint64_t need, const void* keep);
  /// Wakes every waiter and makes later waits return at once (daemon stopping).
  void close();

 private:
  const StreamRegistry& registry_;
  std::mutex mutex_;  ///< every stream's LatestSlot, and the members below
  std::condition_variable changed_;
  uint64_t faces_ids_ = 0;  ///< unique over all streams, so a switched viewer never mixes them
  bool closed_ = false;
};

}  // namespace fq::daemon
