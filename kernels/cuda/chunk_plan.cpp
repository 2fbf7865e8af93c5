// plan_chunks: each chunk through the sequential layout's checks, then its places in the packed
// bytes, the outputs and the tables' room.
#include "kernels/cuda/chunk_plan.h"

#include <string>

#include "wire/frame_codec.h"
#include "wire/rans_decode.h"
#include "wire/sequential_layout.h"

namespace fq::cuda {

fq::Status plan_chunks(const std::vector<std::string_view>& chunks, uint32_t id_limit, ChunkPlan& plan) {
  if (chunks.empty() || chunks.size() > wire::kMaxChunks)
    return invalid_input("a frame has 1 to " + std::to_string(wire::kMaxChunks) + " chunks, not " +
                         std::to_string(chunks.size()));
  plan.jobs.resize(chunks.size());
  plan.ids.resize(chunks.size());
  plan.bytes = plan.points = plan.corners = plan.symbols = 0;
  plan.labelled = false;
  for (size_t i = 0; i < chunks.size(); ++i) {
    const std::string_view bytes = chunks[i];
    wire::detail::SequentialPlan p;
    if (bytes.size() > kMaxDeviceChunkBytes ||
        !wire::detail::plan_sequential_chunk(bytes, id_limit, p, plan.ids[i]))
      return invalid_input("chunk " + std::to_string(i) + " is not a sequential chunk the device decodes");
    const wire::detail::SequentialLayout& l = p.layout;
    ChunkJob& job = plan.jobs[i];
    job.bytes_at = plan.bytes;
    job.first_point = plan.points;
    job.first_corner = plan.corners;
    job.symbols_at = plan.symbols;
    job.size = static_cast<uint32_t>(bytes.size());
    job.corners_at = static_cast<uint32_t>(l.corners_at);
    job.corners_end = static_cast<uint32_t>(p.corners_end);
    job.values_at = static_cast<uint32_t>(p.values_at);
    job.points = l.points;
    job.faces = l.faces;
    job.symbol_room =
        wire::detail::rans_symbol_room(bytes.size() - p.values_at, wire::detail::kRansMaxPrecisionBits);
    job.index_bytes = l.index_bytes;
    job.labelled = l.labelled ? 1 : 0;
    plan.bytes += bytes.size();
    plan.points += l.points;
    plan.corners += 3 * uint64_t(l.faces);
    plan.symbols += job.symbol_room;
    plan.labelled = plan.labelled || l.labelled;
  }
  return {};
}

}  // namespace fq::cuda
