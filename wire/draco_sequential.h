// Draco's sequential coder (meshes and point clouds), written straight from a frame's arrays.
//
// Why not draco::Encoder here: it needs each chunk as a draco::Mesh (a copy of its faces and
// positions) and then makes five passes over that copy (quantize, find the value range,
// predict, map to symbols, entropy-code). Around the entropy coder the sequential format is a
// handful of header fields (Draco's bitstream spec: "Sequential Connectivity", "Sequential
// Attributes"), so the codec writes those itself, quantizes and delta-codes a chunk's values in
// two fused passes straight from the frame, and hands the symbols to Draco's own entropy coder
// (draco::EncodeSymbols). The bytes are exactly those draco::Encoder writes for the same chunk
// (tests/wire/draco_sequential_test.cpp compares them byte for byte), so any Draco decoder
// reads them. Edgebreaker chunks still go through draco::Encoder.
#pragma once

#include <draco/core/encoder_buffer.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "common/scratch_pool.h"
#include "wire/frame_codec.h"
#include "wire/frame_split.h"
#include "wire/varint.h"

namespace fq::wire::detail {

/// The range of the frame's quantization grid: the box's largest side (1 when it is zero, at
/// least 0.000001), as Draco's options hold it (six decimals). encode_on_grid hands Draco this.
float grid_range(const Box& box);

/// Draco's quantization of positions on the frame's explicit grid (its
/// AttributeQuantizationTransform with origin box.lo and range grid_range(box), both rounded to
/// six decimals as Draco's string options round them): the same float operations in the same
/// order, so every value matches draco::Encoder's.
class PositionQuantizer {
 public:
  PositionQuantizer(const Box& box, int bits);
  int32_t operator()(float v, int axis) const {
    float x = v - lo_[axis];
    x *= inverse_delta_;  // two roundings, as Draco's Quantizer (wire/CMakeLists.txt: no FMA contraction)
    return static_cast<int32_t>(std::floor(x + 0.5f));
  }
  /// The transform's parameters as the decoder reads them after the values.
  void write_parameters(draco::EncoderBuffer& out) const;

 private:
  float lo_[3];
  float range_;
  float inverse_delta_;
  int bits_;
};

/// Smallest and largest of a set of integer values: the bounds of Draco's wrap transform.
struct ValueBounds {
  int32_t lo = std::numeric_limits<int32_t>::max();
  int32_t hi = std::numeric_limits<int32_t>::min();
  void add(int32_t v) {
    lo = v < lo ? v : lo;
    hi = v > hi ? v : hi;
  }
};

/// Buffers of one thread's sequential chunks, reused from chunk to chunk and frame to frame:
/// a stream's next frame of about the same size allocates nothing (on a virtual machine the
/// first touch of each fresh page is a fault, which cost more than the coding itself).
struct SequentialScratch {
  std::vector<int32_t> quantized;     ///< 3 quantized coordinates a point
  std::vector<int32_t> label_values;  ///< a label a point
  std::vector<uint32_t> symbols;      ///< Draco symbols of one attribute
  draco::EncoderBuffer buffer;        ///< the chunk being written
};

/// Draco's symbol coder's compression level for the codec's speeds: 10 minus the larger speed.
int symbol_compression_level(const CodecOptions& o);

/// Draco's file header: magic, bitstream version, geometry type, sequential method, flags.
void write_header(draco::EncoderBuffer& out, bool mesh, bool has_metadata);

/// One attribute of a sequential chunk, in the order it is coded.
struct AttributeSpec {
  int type;       ///< draco::GeometryAttribute::Type
  int data_type;  ///< draco::DataType
  int components;
  uint8_t sequential_encoder;  ///< draco::SequentialAttributeEncoderType
};

/// The attribute encoder's description: one encoder, then each attribute (unique ids 0, 1, ...)
/// and its sequential encoder's id.
void write_attribute_specs(draco::EncoderBuffer& out, const std::vector<AttributeSpec>& specs);

/// One attribute's values, as Draco's sequential integer encoder codes them: delta prediction
/// with the wrap transform over `bounds`, signed values as symbols, draco::EncodeSymbols at
/// `level`, then the bounds. `values` holds points * components integers; `symbols` is scratch.
/// False when Draco's symbol coder fails.
bool write_delta_values(const int32_t* values, uint32_t points, int components, ValueBounds bounds, int level,
                        std::vector<uint32_t>& symbols, draco::EncoderBuffer& out);

/// Sequential connectivity: face and point counts, then 3 * faces point indices in Draco's
/// smallest width for `points` (uint8, uint16, varint or uint32), written in place.
/// `for_each_corner(put)` calls put(point index) once per corner, in face order.
template <class ForEachCorner>
void write_connectivity(draco::EncoderBuffer& out, uint32_t faces, uint32_t points,
                        ForEachCorner&& for_each_corner) {
  uint8_t head[11];
  uint8_t* end = put_varint(points, put_varint(faces, head));
  *end++ = 1;  // indices stored directly (Draco's "compress_connectivity" is off)
  out.Encode(head, size_t(end - head));
  std::vector<char>& bytes = *out.buffer();
  const size_t at = bytes.size(), corners = 3 * size_t(faces);
  const auto fixed = [&](auto width_tag) {
    using T = decltype(width_tag);
    bytes.resize(at + corners * sizeof(T));
    char* p = bytes.data() + at;
    for_each_corner([&p](uint32_t i) {
      const auto v = static_cast<T>(i);
      std::memcpy(p, &v, sizeof(T));
      p += sizeof(T);
    });
  };
  if (points < 256) {
    fixed(uint8_t{});
  } else if (points < (1u << 16)) {
    fixed(uint16_t{});
  } else if (points < (1u << 21)) {
    bytes.resize(at + corners * 3);  // at most three bytes for an index below 2^21
    auto* p = reinterpret_cast<uint8_t*>(bytes.data() + at);
    for_each_corner([&p](uint32_t i) { p = put_varint(i, p); });
    bytes.resize(size_t(reinterpret_cast<char*>(p) - bytes.data()));
  } else {
    fixed(uint32_t{});
  }
}

/// The positions of `n` points as a Draco point cloud (sequential coder, POSITION only,
/// quantized on `box`'s grid), the bytes draco::Encoder writes for it. kInternal when Draco's
/// symbol coder fails.
fq::Status write_point_cloud(const float* positions, uint32_t n, const CodecOptions& o, const Box& box,
                             SequentialScratch& scratch, std::string& out);

/// The sequential coder's scratch, borrowed for a chunk and kept for the next ones (each holds
/// what the largest chunk so far needed); wire::release_memory() frees it.
ScratchPool<SequentialScratch>& sequential_scratch();

}  // namespace fq::wire::detail
