// read_sequential_chunk: the fields write_sequential_chunk writes, parsed as Draco's decoder
// parses them (see draco_sequential_read.h); every "return false" hands the chunk to Draco.
#include "wire/draco_sequential_read.h"

#include <draco/attributes/geometry_attribute.h>
#include <draco/compression/config/compression_shared.h>
#include <draco/compression/entropy/symbol_decoding.h>
#include <draco/core/decoder_buffer.h>
#include <draco/core/varint_decoding.h>
#include <draco/metadata/geometry_metadata.h>
#include <draco/metadata/metadata_decoder.h>

#include <cstring>
#include <limits>
#include <string>

#include "wire/frame_codec.h"
#include "wire/varint.h"
#include "wire/vertex_id_runs.h"

namespace fq::wire::detail {
namespace {

template <class T>
bool expect(draco::DecoderBuffer& in, T want) {
  T v{};
  return in.Decode(&v) && v == want;
}

/// Draco's header as write_header writes it: a mesh with metadata, or a point cloud without.
bool read_header(draco::DecoderBuffer& in, bool mesh) {
  char magic[5];
  uint16_t flags = 0;
  if (!in.Decode(magic, 5) || std::memcmp(magic, "DRACO", 5) != 0) return false;
  const bool version = mesh ? expect<uint8_t>(in, draco::kDracoMeshBitstreamVersionMajor) &&
                                  expect<uint8_t>(in, draco::kDracoMeshBitstreamVersionMinor)
                            : expect<uint8_t>(in, draco::kDracoPointCloudBitstreamVersionMajor) &&
                                  expect<uint8_t>(in, draco::kDracoPointCloudBitstreamVersionMinor);
  const bool kind = mesh ? expect<uint8_t>(in, draco::TRIANGULAR_MESH) &&
                               expect<uint8_t>(in, draco::MESH_SEQUENTIAL_ENCODING)
                         : expect<uint8_t>(in, draco::POINT_CLOUD) &&
                               expect<uint8_t>(in, draco::POINT_CLOUD_SEQUENTIAL_ENCODING);
  if (!version || !kind || !in.Decode(&flags) || ((flags & METADATA_FLAG_MASK) != 0) != mesh) return false;
  // As Draco's decoder does, for its symbol coder.
  in.set_bitstream_version(mesh ? draco::kDracoMeshBitstreamVersion
                                : draco::kDracoPointCloudBitstreamVersion);
  return true;
}

/// The geometry metadata: the id runs, and either no attribute metadata or the label's name on
/// the second attribute. Sets `labelled`.
bool read_metadata(draco::DecoderBuffer& in, std::vector<uint8_t>& runs, bool& labelled) {
  draco::GeometryMetadata md;
  if (!draco::MetadataDecoder().DecodeGeometryMetadata(&in, &md)) return false;
  if (!md.GetEntryBinary(kVertexIdRunsEntry, &runs)) return false;
  const auto& atts = md.attribute_metadatas();
  labelled = atts.size() == 1;
  if (atts.size() > 1) return false;
  std::string name;
  return !labelled ||
         (atts[0]->att_unique_id() == 1 && atts[0]->GetEntryString("name", &name) && name == kLabelAttribute);
}

/// Draco's raw sequential connectivity: counts, then 3 * faces indices in the width `points` implies.
bool read_connectivity(draco::DecoderBuffer& in, SequentialChunk& c) {
  if (!draco::DecodeVarint(&c.faces, &in) || !draco::DecodeVarint(&c.points, &in)) return false;
  // Draco's own bounds (MeshSequentialDecoder::DecodeConnectivity).
  const uint64_t faces = c.faces, points = c.points;
  if (faces > 0xffffffffull / 3 || faces > uint64_t(in.remaining_size()) / 3 || points > 3 * faces)
    return false;
  if (faces == 0 || !expect<uint8_t>(in, 1)) return false;  // 1: indices stored directly
  const size_t corners = 3 * size_t(faces);
  c.corners.resize(corners);
  uint32_t* out = c.corners.data();
  const auto* p = reinterpret_cast<const uint8_t*>(in.data_head());
  const auto* end = p + in.remaining_size();
  uint32_t bad = 0;  // any index past the points: decode_frame refuses those faces
  const auto fixed = [&](auto width_tag) {
    using T = decltype(width_tag);
    if (size_t(end - p) < corners * sizeof(T)) return false;
    for (size_t k = 0; k < corners; ++k, p += sizeof(T)) {
      T v;
      std::memcpy(&v, p, sizeof(T));
      out[k] = v;
      bad |= static_cast<uint32_t>(v >= c.points);
    }
    return true;
  };
  bool ok = false;
  if (c.points < 256) {
    ok = fixed(uint8_t{});
  } else if (c.points < (1u << 16)) {
    ok = fixed(uint16_t{});
  } else if (c.points < (1u << 21)) {
    ok = true;
    const auto size = size_t(end - p);
    size_t pos = 0;
    for (size_t k = 0; k < corners && ok; ++k) {  // varints of at most 3 bytes (below 2^21); else Draco
      ok = get_varint(p, size, pos, out[k], 3);
      bad |= static_cast<uint32_t>(out[k] >= c.points);
    }
    p += pos;
  } else {
    ok = fixed(uint32_t{});
  }
  if (!ok || bad != 0) return false;
  in.Advance(p - reinterpret_cast<const uint8_t*>(in.data_head()));
  return true;
}

/// The attribute encoder's description, as write_attribute_specs writes it.
bool read_attribute_specs(draco::DecoderBuffer& in, bool labelled) {
  uint32_t count = 0;
  if (!expect<uint8_t>(in, 1) || !draco::DecodeVarint(&count, &in) || count != (labelled ? 2u : 1u))
    return false;
  const auto spec = [&](int type, int data_type, int components, uint32_t unique_id) {
    uint32_t id = 0;
    return expect<uint8_t>(in, static_cast<uint8_t>(type)) &&
           expect<uint8_t>(in, static_cast<uint8_t>(data_type)) &&
           expect<uint8_t>(in, static_cast<uint8_t>(components)) && expect<uint8_t>(in, 0) &&
           draco::DecodeVarint(&id, &in) && id == unique_id;
  };
  if (!spec(draco::GeometryAttribute::POSITION, draco::DT_FLOAT32, 3, 0)) return false;
  if (labelled && !spec(draco::GeometryAttribute::GENERIC, draco::DT_UINT32, 1, 1)) return false;
  return expect<uint8_t>(in, draco::SEQUENTIAL_ATTRIBUTE_ENCODER_QUANTIZATION) &&
         (!labelled || expect<uint8_t>(in, draco::SEQUENTIAL_ATTRIBUTE_ENCODER_INTEGER));
}

/// One attribute's points * components values into `v`, as Draco's sequential integer decoder
/// computes them: entropy-coded delta corrections with the wrap transform.
bool read_delta_values(draco::DecoderBuffer& in, uint32_t points, int components, int32_t* v) {
  if (!expect<int8_t>(in, draco::PREDICTION_DIFFERENCE) ||
      !expect<int8_t>(in, draco::PREDICTION_TRANSFORM_WRAP) || !expect<uint8_t>(in, 1))  // entropy-coded
    return false;
  const size_t count = size_t(points) * size_t(components);
  auto* sym = reinterpret_cast<uint32_t*>(v);  // decoded in place, as Draco does
  if (!draco::DecodeSymbols(static_cast<uint32_t>(count), components, &in, sym)) return false;
  int32_t lo = 0, hi = 0;
  if (!in.Decode(&lo) || !in.Decode(&hi) || lo > hi) return false;
  // Draco's PredictionSchemeWrapTransformBase::InitCorrectionBounds and its decoding transform.
  const int64_t dif = int64_t(hi) - int64_t(lo);
  if (dif >= std::numeric_limits<int32_t>::max()) return false;
  const auto max_dif = static_cast<uint32_t>(1 + dif);
  for (size_t i = 0; i < count; ++i) {
    const uint32_t s = sym[i];
    const int32_t correction = (s & 1) ? -static_cast<int32_t>(s >> 1) - 1 : static_cast<int32_t>(s >> 1);
    int32_t predicted = i < size_t(components) ? 0 : v[i - size_t(components)];
    predicted = predicted > hi ? hi : (predicted < lo ? lo : predicted);
    auto value = static_cast<int32_t>(static_cast<uint32_t>(predicted) + static_cast<uint32_t>(correction));
    if (value > hi) {
      value = static_cast<int32_t>(static_cast<uint32_t>(value) - max_dif);
    } else if (value < lo) {
      value = static_cast<int32_t>(static_cast<uint32_t>(value) + max_dif);
    }
    v[i] = value;
  }
  return true;
}

/// Draco's quantization parameters, then its dequantization of `points` positions into `out`.
bool dequantize(draco::DecoderBuffer& in, uint32_t points, const int32_t* q, float* out) {
  float origin[3], range = 0.f;
  uint8_t bits = 0;
  if (!in.Decode(origin, sizeof(origin)) || !in.Decode(&range) || !in.Decode(&bits) || bits < 1 || bits > 30)
    return false;
  const auto max_quantized = static_cast<int32_t>((1u << bits) - 1);
  const float delta = range / static_cast<float>(max_quantized);  // Draco's Dequantizer
  for (size_t i = 0; i < 3 * size_t(points); i += 3) {
    for (size_t a = 0; a < 3; ++a) {
      float v =
          static_cast<float>(q[i + a]) * delta;  // two roundings, as Draco (wire.cmake: no FMA contraction)
      out[i + a] = v + origin[a];
    }
  }
  return true;
}

/// The point cloud's header and point count, as write_point_cloud writes them.
bool read_point_cloud_head(draco::DecoderBuffer& in, uint32_t& n) {
  int32_t points = 0;
  if (!read_header(in, false) || !in.Decode(&points) || points < 0) return false;
  // Draco reads the count as it is; a count no genuine chunk of this size could carry (a
  // forged one) is left to Draco's decoder and the caller's limits instead of sizing buffers.
  if (uint64_t(points) > 1024 * uint64_t(in.remaining_size())) return false;
  n = static_cast<uint32_t>(points);
  return true;
}

}  // namespace

bool read_sequential_chunk(std::string_view bytes, uint32_t id_limit, SequentialChunk& c) {
  draco::DecoderBuffer in;
  in.Init(bytes.data(), bytes.size());
  std::vector<uint8_t> runs;
  bool labelled = false;
  if (!read_header(in, true) || !read_metadata(in, runs, labelled) || !read_connectivity(in, c) ||
      !read_attribute_specs(in, labelled))
    return false;
  if (!detail::decode_id_runs(runs.data(), runs.size(), c.points, id_limit, c.ids)) return false;
  c.values.resize(3 * size_t(c.points));
  if (!read_delta_values(in, c.points, 3, c.values.data())) return false;
  // Draco stores the label values (int32) into the uint32 attribute as they are.
  c.labels.resize(labelled ? c.points : 0);
  if (labelled && !read_delta_values(in, c.points, 1, reinterpret_cast<int32_t*>(c.labels.data())))
    return false;
  c.positions.resize(3 * size_t(c.points));
  return dequantize(in, c.points, c.values.data(), c.positions.data());
}

bool sequential_point_count(std::string_view bytes, uint32_t& n) {
  draco::DecoderBuffer in;
  in.Init(bytes.data(), bytes.size());
  return read_point_cloud_head(in, n);
}

bool read_sequential_point_cloud(std::string_view bytes, uint32_t n, float* out,
                                 std::vector<int32_t>& values) {
  draco::DecoderBuffer in;
  in.Init(bytes.data(), bytes.size());
  uint32_t declared = 0;
  if (n == 0 || !read_point_cloud_head(in, declared) || declared != n || !read_attribute_specs(in, false))
    return false;
  values.resize(3 * size_t(n));
  return read_delta_values(in, n, 3, values.data()) && dequantize(in, n, values.data(), out);
}

}  // namespace fq::wire::detail
