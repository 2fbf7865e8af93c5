// The global vertex ids of a chunk's points, carried as runs instead of a Draco attribute.
//
// Chunk points are stored in ascending global id, and Draco's sequential coder keeps point
// order, so a sequentially coded chunk needs only the sorted id list, not a per-point
// attribute. Ids of a spatially coherent chunk come in long runs of consecutive values; the
// list is (gap, run length) pairs, each a LEB128 varint: gap = first id of the run minus the
// end of the previous run (0 at the start), run length >= 1. Encoding and decoding are one
// linear pass, where Draco's integer attribute coder (prediction + entropy coding) cost about
// as much as the positions themselves.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace fq::wire::detail {

/// Writes ascending ids as runs one id at a time, so that a chunk's ids are coded while its
/// points are gathered (no pass of their own).
class IdRunWriter {
 public:
  /// Appends `id` (greater than every id before it).
  void add(uint32_t id) {
    if (length_ != 0 && id == first_ + length_) {
      ++length_;
      return;
    }
    flush();
    first_ = id;
    length_ = 1;
  }
  /// The runs of every id added; the writer is empty again.
  std::vector<uint8_t> finish();

 private:
  void flush();
  std::vector<uint8_t> bytes_;
  uint32_t end_ = 0;  ///< one past the last id of the previous run
  uint32_t first_ = 0, length_ = 0;
};

/// The ids of `size` bytes of runs into `ids`: false when the bytes are malformed, when the
/// ids are not exactly `count`, or when an id reaches `limit`. Never allocates beyond `count`.
bool decode_id_runs(const uint8_t* data, size_t size, size_t count, uint32_t limit,
                    std::vector<uint32_t>& ids);

}  // namespace fq::wire::detail
