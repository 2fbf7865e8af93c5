// fqd's per-stream cluster id tracking: each stream that clusters with track_ids on keeps
// its previous frame's vertices and ids (kernels/label_tracking.h) in its Stream's track
// (stream.h), so that a region keeps its id, and its colour, from frame to frame. Streams do
// not wait on each other; the track goes with its stream. Its bytes are charged to the host
// memory budget (memory_account.h), which may drop it (counted `memory_resets`).
#pragma once

#include <cstdint>

#include "core/cancel_token.h"
#include "daemon/stream/frame_job.h"

namespace fq::daemon {

/// Host bytes of a stream's track a vertex (kernels/label_tracking.h: the previous frame's
/// grid, ids and votes, and the buffers the next frame is tracked in).
inline constexpr uint64_t kLabelTrackBytesPerVertex = 120;

/// For a clustered frame of a stream with track_ids on: replaces the labels by the stream's
/// stable ids and result.num_clusters by their bound (f.distinct_clusters keeps the count).
/// Otherwise forgets the stream's previous frame, so tracking restarts cleanly.
/// kCancelled when `token` expired first: the frame keeps the engine's numbering and the
/// stream's next frame is matched with the last one tracked.
Status track_labels(FrameJob& f, int threads, const CancelToken& token);

}  // namespace fq::daemon
