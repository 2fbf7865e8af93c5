// The pipeline's side of the host memory budget (daemon/stream/memory_account.h): the order in
// which room is made when a charge would pass caps.memory_budget_mb, and the charge of a frame
// from admission to publish.
#pragma once

#include <cstdint>

#include "daemon/stream/frame_job.h"
#include "daemon/stream/latest_results.h"
#include "daemon/stream/memory_account.h"
#include "daemon/stream/stream_registry.h"

namespace fq::daemon {

/// Host bytes of a frame a vertex once decoded: its positions (12) and triangles (about two a
/// vertex, 24), the engine's result positions (12) and cluster labels (4).
inline constexpr uint64_t kFrameBytesPerVertex = 52;

/// Makes room for `need` bytes in the order of memory_account.h, as far as `upto`, never
/// taking from `keep`: /latest copies of streams nobody watches, then, stream by stream from
/// the one whose history a frame used longest ago, temporal histories and cluster id tracks
/// (each stream that loses one counts `memory_resets`). A stream whose history or track a
/// frame is using now is passed over (its lock is busy).
void shed_memory(StreamRegistry& registry, LatestResults& latest, uint64_t need, Shed upto, const void* keep);

/// What frame `f` holds in host memory: its received chunks and, from its vertex count (the
/// header's before decode, the mesh's after), what decode and the engine make of it.
uint64_t frame_bytes(const FrameJob& f);

/// Charges (or charges again, after decode) `f` to its stream's budget, making room as far as
/// histories. False when it does not fit: `f` is counted `dropped_memory` and the caller drops it.
bool charge_frame(FrameJob& f);

}  // namespace fq::daemon
