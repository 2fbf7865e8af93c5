// read_sequential_chunk: the layout parsed by wire/sequential_layout.h, the connectivity read
// here, the symbols decoded by Draco's own symbol decoder (draco::DecodeSymbols) and the rest
// by wire/sequential_values.h, which the device decoder shares; every "return false" hands
// the chunk to Draco.
#include "wire/draco_sequential_read.h"

#include <draco/compression/config/compression_shared.h>
#include <draco/compression/entropy/symbol_decoding.h>
#include <draco/core/decoder_buffer.h>

#include <cstring>

#include "wire/byte_reader.h"
#include "wire/frame_codec.h"
#include "wire/sequential_layout.h"
#include "wire/sequential_values.h"
#include "wire/varint.h"
#include "wire/vertex_id_runs.h"

namespace fq::wire::detail {

static_assert(kPredictionDifference == draco::PREDICTION_DIFFERENCE);
static_assert(kPredictionTransformWrap == draco::PREDICTION_TRANSFORM_WRAP);

namespace {

ByteReader reader_at(std::string_view bytes, size_t at) {
  return ByteReader{reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), at};
}

/// The 3 * faces point indices at l.corners_at into c.corners; `end` is set past them.
bool read_corners(std::string_view bytes, const SequentialLayout& l, SequentialChunk& c, size_t& end) {
  const size_t corners = 3 * size_t(l.faces);
  c.corners.resize(corners);
  uint32_t* out = c.corners.data();
  const auto* p = reinterpret_cast<const uint8_t*>(bytes.data()) + l.corners_at;
  const size_t room = bytes.size() - l.corners_at;
  uint32_t bad = 0;  // any index past the points: decode_frame refuses those faces
  const auto fixed = [&](auto width_tag) {
    using T = decltype(width_tag);
    if (room / sizeof(T) < corners) return false;
    for (size_t k = 0; k < corners; ++k, p += sizeof(T)) {
      T v;
      std::memcpy(&v, p, sizeof(T));
      out[k] = v;
      bad |= static_cast<uint32_t>(v >= l.points);
    }
    end = l.corners_at + corners * sizeof(T);
    return true;
  };
  bool ok = false;
  if (l.index_bytes == 1) {
    ok = fixed(uint8_t{});
  } else if (l.index_bytes == 2) {
    ok = fixed(uint16_t{});
  } else if (l.index_bytes == 0) {
    ok = true;
    size_t pos = 0;
    for (size_t k = 0; k < corners && ok; ++k) {  // varints of at most 3 bytes (below 2^21); else Draco
      ok = get_varint(p, room, pos, out[k], 3);
      bad |= static_cast<uint32_t>(out[k] >= l.points);
    }
    end = l.corners_at + pos;
  } else {
    ok = fixed(uint32_t{});
  }
  return ok && bad == 0;
}

/// One attribute's points * components values into `v`, as Draco's sequential integer decoder
/// computes them: entropy-coded delta corrections with the wrap transform.
bool read_delta_values(ByteReader& in, uint16_t bitstream_version, uint32_t points, int components,
                       int32_t* v) {
  if (!read_delta_head(in)) return false;
  const size_t count = size_t(points) * size_t(components);
  draco::DecoderBuffer symbols;
  symbols.Init(reinterpret_cast<const char*>(in.data), in.size, bitstream_version);
  symbols.StartDecodingFrom(int64_t(in.pos));
  // Decoded in place, as Draco does.
  if (!draco::DecodeSymbols(static_cast<uint32_t>(count), components, &symbols,
                            reinterpret_cast<uint32_t*>(v)))
    return false;
  in.pos = size_t(symbols.decoded_size());
  WrapBounds bounds;
  if (!read_wrap_bounds(in, bounds)) return false;
  unwrap_values(v, count, size_t(components), bounds);
  return true;
}

/// Draco's quantization parameters, then its dequantization of `points` positions into `out`.
bool dequantize_positions(ByteReader& in, uint32_t points, const int32_t* q, float* out) {
  Quantization params;
  if (!read_quantization(in, params)) return false;
  for (size_t i = 0; i < 3 * size_t(points); i += 3) {
    for (int a = 0; a < 3; ++a) out[i + size_t(a)] = dequantize(q[i + size_t(a)], params, a);
  }
  return true;
}

}  // namespace

bool read_sequential_chunk(std::string_view bytes, uint32_t id_limit, SequentialChunk& c) {
  SequentialLayout l;
  std::vector<uint8_t> runs;
  size_t corners_end = 0, values_at = 0;
  if (!read_sequential_layout(bytes, l, runs) || !read_corners(bytes, l, c, corners_end) ||
      !read_attribute_specs(bytes, corners_end, l.labelled, values_at))
    return false;
  c.points = l.points;
  c.faces = l.faces;
  if (!detail::decode_id_runs(runs.data(), runs.size(), c.points, id_limit, c.ids)) return false;
  ByteReader in = reader_at(bytes, values_at);
  c.values.resize(3 * size_t(c.points));
  if (!read_delta_values(in, draco::kDracoMeshBitstreamVersion, c.points, 3, c.values.data())) return false;
  // Draco stores the label values (int32) into the uint32 attribute as they are.
  c.labels.resize(l.labelled ? c.points : 0);
  if (l.labelled && !read_delta_values(in, draco::kDracoMeshBitstreamVersion, c.points, 1,
                                       reinterpret_cast<int32_t*>(c.labels.data())))
    return false;
  c.positions.resize(3 * size_t(c.points));
  return dequantize_positions(in, c.points, c.values.data(), c.positions.data());
}

bool sequential_point_count(std::string_view bytes, uint32_t& n) {
  size_t specs_at = 0;
  return read_point_cloud_head(bytes, n, specs_at);
}

bool read_sequential_point_cloud(std::string_view bytes, uint32_t n, float* out,
                                 std::vector<int32_t>& values) {
  uint32_t declared = 0;
  size_t specs_at = 0, values_at = 0;
  if (n == 0 || !read_point_cloud_head(bytes, declared, specs_at) || declared != n ||
      !read_attribute_specs(bytes, specs_at, false, values_at))
    return false;
  values.resize(3 * size_t(n));
  ByteReader in = reader_at(bytes, values_at);
  return read_delta_values(in, draco::kDracoPointCloudBitstreamVersion, n, 3, values.data()) &&
         dequantize_positions(in, n, values.data(), out);
}

}  // namespace fq::wire::detail
