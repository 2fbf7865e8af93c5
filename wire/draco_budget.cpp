#include "wire/draco_budget.h"

#include <string>

namespace fq::wire {
namespace {

// Field layout from the Draco bitstream specification (2.2): header, optional metadata,
// then the connectivity counts of the sequential or the edgebreaker mesh coder.
constexpr uint16_t kMetadataFlag = 0x8000;
constexpr uint8_t kTriangularMesh = 1;
constexpr uint8_t kSequential = 0;
constexpr uint8_t kEdgebreaker = 1;
constexpr int kMaxMetadataDepth = 8;  // fq writes depth 1; deeper nesting is refused

class Reader {
 public:
  explicit Reader(std::string_view b) : b_(b) {}
  bool u8(uint8_t& v) {
    if (pos_ >= b_.size()) return false;
    v = static_cast<uint8_t>(b_[pos_++]);
    return true;
  }
  bool u16(uint16_t& v) {
    uint8_t lo, hi;
    if (!u8(lo) || !u8(hi)) return false;
    v = static_cast<uint16_t>(lo | (hi << 8));
    return true;
  }
  bool varint(uint64_t& v) {  // LEB128, at most 32 bits as Draco writes them
    v = 0;
    for (int shift = 0; shift < 35; shift += 7) {
      uint8_t byte;
      if (!u8(byte)) return false;
      v |= uint64_t(byte & 0x7f) << shift;
      if (!(byte & 0x80)) return v <= 0xffffffffull;
    }
    return false;
  }
  bool skip(size_t n) {
    if (b_.size() - pos_ < n) return false;
    pos_ += n;
    return true;
  }
  size_t remaining() const { return b_.size() - pos_; }

 private:
  std::string_view b_;
  size_t pos_ = 0;
};

// Every entry and sub-metadata takes at least one byte, so counts above the bytes left
// are forged; checking that keeps the walk linear in the chunk size.
bool skip_metadata_element(Reader& r, int depth) {
  if (depth > kMaxMetadataDepth) return false;
  uint64_t entries;
  if (!r.varint(entries) || entries > r.remaining()) return false;
  for (uint64_t i = 0; i < entries; ++i) {
    // Key: one length byte. Value: a varint length (Draco's encoder; the same byte as the
    // specification's UI8 for values under 128 bytes, and binary entries can be longer).
    uint8_t key;
    uint64_t value;
    if (!r.u8(key) || !r.skip(key) || !r.varint(value) || value > r.remaining() || !r.skip(value))
      return false;
  }
  uint64_t subs;
  if (!r.varint(subs) || subs > r.remaining()) return false;
  for (uint64_t i = 0; i < subs; ++i) {
    uint8_t n;
    if (!r.u8(n) || !r.skip(n) || !skip_metadata_element(r, depth + 1)) return false;
  }
  return true;
}

bool skip_metadata(Reader& r) {
  uint64_t attributes;
  if (!r.varint(attributes) || attributes > r.remaining()) return false;
  for (uint64_t i = 0; i < attributes; ++i) {
    uint64_t id;
    if (!r.varint(id) || !skip_metadata_element(r, 0)) return false;
  }
  return skip_metadata_element(r, 0);  // the file's own metadata
}

Status cut_short(const char* what) {
  return invalid_input(std::string("Draco chunk cut short or malformed in its ") + what);
}

}  // namespace

StatusOr<ChunkCounts> read_chunk_counts(std::string_view chunk) {
  Reader r(chunk);
  ChunkCounts out;
  if (chunk.size() < 5 || chunk.substr(0, 5) != "DRACO")
    return invalid_input("not Draco data (no DRACO magic)");
  r.skip(5);
  uint8_t major, minor, type, method;
  uint16_t flags;
  if (!r.u8(major) || !r.u8(minor) || !r.u8(type) || !r.u8(method) || !r.u16(flags))
    return cut_short("header");
  if (type != kTriangularMesh) return invalid_input("a Draco point cloud, not a triangle mesh");
  if (major != 2 || minor != 2)
    return invalid_input("Draco mesh bitstream " + std::to_string(major) + "." + std::to_string(minor) +
                         " is not supported (fq reads 2.2, written by Draco 1.3 and later)");
  if ((flags & kMetadataFlag) && !skip_metadata(r)) return cut_short("metadata");
  if (method == kSequential) {
    if (!r.varint(out.faces) || !r.varint(out.points)) return cut_short("connectivity counts");
    return out;
  }
  if (method == kEdgebreaker) {
    uint8_t traversal, attribute_data;
    uint64_t vertices, symbols, splits;
    if (!r.u8(traversal) || !r.varint(vertices) || !r.varint(out.faces) || !r.u8(attribute_data) ||
        !r.varint(symbols) || !r.varint(splits))
      return cut_short("connectivity counts");
    // Vertex ids the edgebreaker decoder allocates for: encoded vertices plus one per split.
    out.points = vertices + splits;
    return out;
  }
  return invalid_input("unknown Draco mesh encoding method " + std::to_string(method));
}

Status check_chunk_budget(std::string_view chunk, const ChunkBudget& budget) {
  FQ_ASSIGN_OR_RETURN(const ChunkCounts c, read_chunk_counts(chunk));
  const uint64_t carry = budget.max_items_per_byte * chunk.size();
  const uint64_t max_faces = 2 * budget.max_points + 16;  // a closed mesh has about 2 faces per vertex
  auto refuse = [&](const char* what, uint64_t n, const std::string& limit) {
    return invalid_input("Draco chunk of " + std::to_string(chunk.size()) + " bytes declares " +
                         std::to_string(n) + " " + what + ", over " + limit);
  };
  if (c.points > budget.max_points)
    return refuse("points", c.points, "the cap of " + std::to_string(budget.max_points));
  if (c.faces > max_faces) return refuse("faces", c.faces, "the cap of " + std::to_string(max_faces));
  if (c.points > carry)
    return refuse("points", c.points, "what its bytes can carry (" + std::to_string(carry) + ")");
  if (c.faces > carry)
    return refuse("faces", c.faces, "what its bytes can carry (" + std::to_string(carry) + ")");
  return {};
}

}  // namespace fq::wire
