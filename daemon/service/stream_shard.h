// Streams spread over N fqd processes by their id (topic sharding without a hand-written
// list per process): process K of N serves the ids of [ingest] streams whose hash modulo N is
// K. The hash is 32-bit FNV-1a of the id's bytes, so any client can compute where a stream
// goes (`fqd --shard-map N` prints it) and the assignment never depends on the list's order.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "common/status.h"

namespace fq::daemon {

struct SubIngestConfig;

/// 32-bit FNV-1a of `id` (offset basis 2166136261, prime 16777619).
uint32_t stream_hash(std::string_view id);

/// The shard (0..count-1) that serves `id`.
uint32_t shard_of(std::string_view id, uint32_t count);

/// "K/N": K an ordinal, or a StatefulSet pod name ending in "-K" (fqd-2/3); 0 <= K < N.
Status parse_shard(const std::string& text, uint32_t& index, uint32_t& count);

/// Keeps the [ingest] streams of shard `index` of `count`. Returns the ids kept. With none
/// left, `connect` is cleared too (an empty list would mean every stream): the process then
/// serves its PULL socket only.
std::vector<std::string> keep_shard(SubIngestConfig& sub, uint32_t index, uint32_t count);

}  // namespace fq::daemon
