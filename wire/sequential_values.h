// The attribute values of a sequential chunk around their symbols, as Draco's sequential
// integer and quantization decoders compute them, in host+device code: the prediction's head,
// the wrap transform's bounds and its decoding of the delta corrections, the quantization's
// parameters and the dequantization. read_sequential_chunk (host, with Draco's symbol decoder)
// and the device decoder (kernels/cuda/chunk_decode.cu, with wire/symbol_decode.h) both use
// these, so that they compute the same values.
#pragma once

#include <cstddef>
#include <cstdint>

#include "common/hd.h"
#include "wire/byte_reader.h"

namespace fq::wire::detail {

/// Draco's PREDICTION_DIFFERENCE and PREDICTION_TRANSFORM_WRAP (draco_sequential_read.cpp
/// checks them against Draco's headers).
inline constexpr int8_t kPredictionDifference = 0;
inline constexpr int8_t kPredictionTransformWrap = 1;

/// The head write_delta_values writes before the symbols: difference prediction, the wrap
/// transform, entropy-coded.
FQ_HD bool read_delta_head(ByteReader& in) {
  return in.expect<int8_t>(kPredictionDifference) && in.expect<int8_t>(kPredictionTransformWrap) &&
         in.expect<uint8_t>(1);
}

/// The wrap transform's bounds (after the symbols), as Draco's
/// PredictionSchemeWrapTransformBase::InitCorrectionBounds takes them.
struct WrapBounds {
  int32_t lo = 0, hi = 0;
  uint32_t max_dif = 1;  ///< 1 + hi - lo
};

FQ_HD bool read_wrap_bounds(ByteReader& in, WrapBounds& w) {
  if (!in.get(w.lo) || !in.get(w.hi) || w.lo > w.hi) return false;
  const int64_t dif = int64_t(w.hi) - int64_t(w.lo);
  if (dif >= int64_t(0x7fffffff)) return false;
  w.max_dif = static_cast<uint32_t>(1 + dif);
  return true;
}

/// Draco's wrap decoding of one value from its predictor (the previous point's value, 0 for
/// the first point) and its symbol (a signed correction as Draco maps it to a symbol).
FQ_HD int32_t unwrap(int32_t predicted, uint32_t symbol, const WrapBounds& w) {
  const int32_t correction =
      (symbol & 1) ? -static_cast<int32_t>(symbol >> 1) - 1 : static_cast<int32_t>(symbol >> 1);
  predicted = predicted > w.hi ? w.hi : (predicted < w.lo ? w.lo : predicted);
  auto value = static_cast<int32_t>(static_cast<uint32_t>(predicted) + static_cast<uint32_t>(correction));
  if (value > w.hi) {
    value = static_cast<int32_t>(static_cast<uint32_t>(value) - w.max_dif);
  } else if (value < w.lo) {
    value = static_cast<int32_t>(static_cast<uint32_t>(value) + w.max_dif);
  }
  return value;
}

/// Decodes `count` values of `components` each in place: v holds their symbols (Draco decodes
/// them into the same buffer) and gets the values, each predicted by the one `components` before.
FQ_HD void unwrap_values(int32_t* v, size_t count, size_t components, const WrapBounds& w) {
  for (size_t i = 0; i < count; ++i)
    v[i] = unwrap(i < components ? 0 : v[i - components], static_cast<uint32_t>(v[i]), w);
}

/// Draco's quantization parameters after the values: origin, range, bits; `delta` is Draco's
/// Dequantizer step, range / (2^bits - 1).
struct Quantization {
  float origin[3] = {0, 0, 0};
  float delta = 0;
};

FQ_HD bool read_quantization(ByteReader& in, Quantization& q) {
  float range = 0.f;
  uint8_t bits = 0;
  if (!in.get(q.origin[0]) || !in.get(q.origin[1]) || !in.get(q.origin[2]) || !in.get(range) ||
      !in.get(bits) || bits < 1 || bits > 30)
    return false;
  q.delta = range / static_cast<float>(static_cast<int32_t>((1u << bits) - 1));
  return true;
}

/// Draco's dequantization of one coordinate: a multiply, then an add, two roundings (no
/// fused multiply-add: the host files that call this build with -ffp-contract=off).
FQ_HD float dequantize(int32_t v, const Quantization& q, int axis) {
#if defined(__CUDA_ARCH__)
  return __fadd_rn(__fmul_rn(static_cast<float>(v), q.delta), q.origin[axis]);
#else
  const float scaled = static_cast<float>(v) * q.delta;
  return scaled + q.origin[axis];
#endif
}

}  // namespace fq::wire::detail
