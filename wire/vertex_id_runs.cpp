#include "wire/vertex_id_runs.h"

#include "wire/varint.h"

namespace fq::wire::detail {
void IdRunWriter::flush() {
  if (length_ == 0) return;
  uint8_t buf[10];  // two varints of at most 5 bytes
  uint8_t* at = put_varint(first_ - end_, buf);
  at = put_varint(length_, at);
  bytes_.insert(bytes_.end(), buf, at);
  end_ = first_ + length_;
}

std::vector<uint8_t> IdRunWriter::finish() {
  flush();
  std::vector<uint8_t> out = std::move(bytes_);
  *this = {};
  return out;
}

bool decode_id_runs(const uint8_t* data, size_t size, size_t count, uint32_t limit,
                    std::vector<uint32_t>& ids) {
  ids.resize(count);
  size_t filled = 0;
  uint64_t end = 0;
  for (size_t pos = 0; pos < size;) {
    uint32_t gap = 0, run = 0;
    if (!get_varint(data, size, pos, gap) || !get_varint(data, size, pos, run) || run == 0) return false;
    const uint64_t first = end + gap;
    end = first + run;
    if (end > limit || filled + run > count) return false;
    for (uint32_t k = 0; k < run; ++k) ids[filled + k] = static_cast<uint32_t>(first + k);
    filled += run;
  }
  return filled == count;
}

}  // namespace fq::wire::detail
