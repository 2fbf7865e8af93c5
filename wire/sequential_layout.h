// The layout of the frame codec's own sequential chunks and POSITIONS point clouds (as
// write_sequential_chunk and write_point_cloud write them) up to their attribute values,
// parsed as Draco's decoder parses it. One parser for both readers of those bytes:
// read_sequential_chunk on the host, and the host's checks of every chunk before the device
// decoder takes it (kernels/cuda/chunk_decoder.h), so that both take a chunk on the same terms.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

namespace fq::wire::detail {

/// A sequential chunk up to its connectivity indices.
struct SequentialLayout {
  uint32_t points = 0;
  uint32_t faces = 0;
  uint8_t index_bytes = 0;  ///< sequential_index_bytes(points)
  bool labelled = false;    ///< the chunk has the "fq_label" attribute
  size_t corners_at = 0;    ///< offset of the first connectivity index
};

/// Draco's width of a raw connectivity index for `points` points: 1, 2 or 4 bytes, or 0 for
/// varints (points in [2^16, 2^21): at most 3 bytes each).
constexpr uint8_t sequential_index_bytes(uint32_t points) {
  return points < 256 ? 1 : (points < (1u << 16) ? 2 : (points < (1u << 21) ? 0 : 4));
}

/// Draco's header (a mesh with metadata), the metadata (the id runs into `runs`, the label's
/// name) and the connectivity's counts with Draco's bounds on them, up to the first index.
/// False when `bytes` are not laid out as write_sequential_chunk writes them.
bool read_sequential_layout(std::string_view bytes, SequentialLayout& layout, std::vector<uint8_t>& runs);

/// The end of the connectivity (just past its 3 * faces indices): false when they do not fit
/// in `bytes` or a varint index is longer than 3 bytes (read_sequential_chunk refuses both).
bool sequential_corners_end(std::string_view bytes, const SequentialLayout& layout, size_t& end);

/// The attribute encoder's description at `at` (POSITION, and "fq_label" when `labelled`, as
/// write_attribute_specs writes them); `values_at` is set just past it.
bool read_attribute_specs(std::string_view bytes, size_t at, bool labelled, size_t& values_at);

/// A sequential chunk checked up to its attribute values.
struct SequentialPlan {
  SequentialLayout layout;
  size_t corners_end = 0;  ///< just past the connectivity
  size_t values_at = 0;    ///< the first attribute's values
};

/// Every check read_sequential_chunk makes before the attribute values but the indices'
/// bounds (the device decoder checks those as it reads them): the layout, the connectivity's
/// extent, the attribute description, and the ids (their runs decoded into `ids`, each below
/// `id_limit`). `plan` says where the rest lies.
bool plan_sequential_chunk(std::string_view bytes, uint32_t id_limit, SequentialPlan& plan,
                           std::vector<uint32_t>& ids);

/// A POSITIONS point cloud's header and point count `n` (write_point_cloud); `specs_at` is set
/// just past the count, where its attribute description starts.
bool read_point_cloud_head(std::string_view bytes, uint32_t& n, size_t& specs_at);

}  // namespace fq::wire::detail
