// Draco's sequential format around its entropy coder (see draco_sequential.h for why).
#include "wire/draco_sequential.h"

#include <draco/attributes/geometry_attribute.h>
#include <draco/compression/config/compression_shared.h>
#include <draco/compression/entropy/symbol_encoding.h>
#include <draco/core/options.h>
#include <draco/core/varint_encoding.h>

#include <algorithm>
#include <cstdlib>
#include <string>

namespace fq::wire::detail {

namespace {

/// A float as Draco's options hold it: std::to_string (six decimals), read back with strtof.
float option_vector_value(float v) { return std::strtof(std::to_string(v).c_str(), nullptr); }
/// A float as Draco's Options::SetFloat / GetFloat hold it: std::to_string, then atof.
float option_float_value(float v) { return static_cast<float>(std::atof(std::to_string(v).c_str())); }

}  // namespace

float grid_range(const Box& box) {
  const float extent = box.max_extent();
  const float range = option_float_value(extent > 0.f ? extent : 1.f);
  // A frame smaller than a micrometre would get a range of zero (an infinite scale); Draco's
  // options can hold no smaller positive range than 0.000001.
  return range > 0.f ? range : option_float_value(1e-6f);
}

PositionQuantizer::PositionQuantizer(const Box& box, int bits) : bits_(bits) {
  // Draco keeps the explicit grid's origin and range in its string options, so the grid it
  // quantizes on is the one given rounded to six decimals.
  for (int a = 0; a < 3; ++a) lo_[a] = option_vector_value(box.lo[a]);
  range_ = grid_range(box);
  // Draco's Quantizer::Init(range, max_quantized_value).
  inverse_delta_ = static_cast<float>(static_cast<int32_t>((1u << bits) - 1)) / range_;
}

void PositionQuantizer::write_parameters(draco::EncoderBuffer& out) const {
  out.Encode(lo_, sizeof(lo_));
  out.Encode(range_);
  out.Encode(static_cast<uint8_t>(bits_));
}

int symbol_compression_level(const CodecOptions& o) { return 10 - std::max(o.encode_speed, o.decode_speed); }

void write_header(draco::EncoderBuffer& out, bool mesh, bool has_metadata) {
  out.Encode("DRACO", 5);
  out.Encode(mesh ? draco::kDracoMeshBitstreamVersionMajor : draco::kDracoPointCloudBitstreamVersionMajor);
  out.Encode(mesh ? draco::kDracoMeshBitstreamVersionMinor : draco::kDracoPointCloudBitstreamVersionMinor);
  out.Encode(static_cast<uint8_t>(mesh ? draco::TRIANGULAR_MESH : draco::POINT_CLOUD));
  const auto method = static_cast<uint8_t>(mesh ? static_cast<int>(draco::MESH_SEQUENTIAL_ENCODING)
                                                : static_cast<int>(draco::POINT_CLOUD_SEQUENTIAL_ENCODING));
  out.Encode(method);
  const uint16_t flags = has_metadata ? METADATA_FLAG_MASK : 0;
  out.Encode(flags);
}

void write_attribute_specs(draco::EncoderBuffer& out, const std::vector<AttributeSpec>& specs) {
  out.Encode(static_cast<uint8_t>(1));  // one attributes encoder (the sequential controller)
  draco::EncodeVarint(static_cast<uint32_t>(specs.size()), &out);
  for (size_t i = 0; i < specs.size(); ++i) {
    out.Encode(static_cast<uint8_t>(specs[i].type));
    out.Encode(static_cast<uint8_t>(specs[i].data_type));
    out.Encode(static_cast<uint8_t>(specs[i].components));
    out.Encode(static_cast<uint8_t>(0));                  // not normalized
    draco::EncodeVarint(static_cast<uint32_t>(i), &out);  // unique id: the attribute's index
  }
  for (const AttributeSpec& s : specs) out.Encode(s.sequential_encoder);
}

bool write_delta_values(const int32_t* values, uint32_t points, int components, ValueBounds bounds, int level,
                        std::vector<uint32_t>& symbols, draco::EncoderBuffer& out) {
  out.Encode(static_cast<int8_t>(draco::PREDICTION_DIFFERENCE));
  out.Encode(static_cast<int8_t>(draco::PREDICTION_TRANSFORM_WRAP));
  // Draco's PredictionSchemeWrapTransformBase::InitCorrectionBounds.
  const int32_t max_dif = 1 + (bounds.hi - bounds.lo);
  int32_t max_correction = max_dif / 2;
  const int32_t min_correction = -max_correction;
  if ((max_dif & 1) == 0) max_correction -= 1;
  const size_t count = size_t(points) * size_t(components);
  symbols.resize(count);
  uint32_t* sym = symbols.data();
  // A value is predicted by the previous point's; the first point by zero clamped into the
  // bounds. The correction wraps into [min_correction, max_correction] and is mapped to a
  // symbol as Draco's ConvertSignedIntToSymbol does.
  const auto code = [&](size_t i, int32_t predicted) {
    int32_t c = values[i] - predicted;
    if (c < min_correction) {
      c += max_dif;
    } else if (c > max_correction) {
      c -= max_dif;
    }
    sym[i] = c >= 0 ? static_cast<uint32_t>(c) << 1 : (static_cast<uint32_t>(-(c + 1)) << 1) | 1u;
  };
  const int32_t first_prediction = std::min(std::max(0, bounds.lo), bounds.hi);
  for (size_t i = 0; i < size_t(components) && i < count; ++i) code(i, first_prediction);
  for (size_t i = size_t(components); i < count; ++i) code(i, values[i - size_t(components)]);
  out.Encode(static_cast<uint8_t>(1));  // entropy-coded (Draco's built-in attribute compression)
  draco::Options options;
  draco::SetSymbolEncodingCompressionLevel(&options, level);
  if (!draco::EncodeSymbols(sym, static_cast<int>(count), components, &options, &out)) return false;
  out.Encode(bounds.lo);
  out.Encode(bounds.hi);
  return true;
}

fq::Status write_point_cloud(const float* positions, uint32_t n, const CodecOptions& o, const Box& box,
                             SequentialScratch& scratch, std::string& out) {
  const PositionQuantizer quantize(box, o.position_bits);
  std::vector<int32_t>& q = scratch.quantized;
  q.resize(3 * size_t(n));
  ValueBounds bounds;
  for (size_t i = 0; i < 3 * size_t(n); i += 3) {
    for (int a = 0; a < 3; ++a) {
      q[i + size_t(a)] = quantize(positions[i + size_t(a)], a);
      bounds.add(q[i + size_t(a)]);
    }
  }
  draco::EncoderBuffer& buf = scratch.buffer;
  buf.Clear();  // keeps its capacity
  write_header(buf, false, false);
  buf.Encode(static_cast<int32_t>(n));
  write_attribute_specs(buf, {{draco::GeometryAttribute::POSITION, draco::DT_FLOAT32, 3,
                               draco::SEQUENTIAL_ATTRIBUTE_ENCODER_QUANTIZATION}});
  if (n > 0 &&
      !write_delta_values(q.data(), n, 3, bounds, symbol_compression_level(o), scratch.symbols, buf)) {
    return {fq::StatusCode::kInternal, "Draco's symbol coder failed"};
  }
  quantize.write_parameters(buf);
  out.assign(buf.data(), buf.size());
  return {};
}

ScratchPool<SequentialScratch>& sequential_scratch() {
  static ScratchPool<SequentialScratch> pool;
  return pool;
}

}  // namespace fq::wire::detail
