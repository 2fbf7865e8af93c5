// The sequential layout's fields, parsed as Draco's decoder parses them (see
// sequential_layout.h); every "return false" leaves the chunk to Draco's decoder.
#include "wire/sequential_layout.h"

#include <draco/attributes/geometry_attribute.h>
#include <draco/compression/config/compression_shared.h>
#include <draco/core/decoder_buffer.h>
#include <draco/core/varint_decoding.h>
#include <draco/metadata/geometry_metadata.h>
#include <draco/metadata/metadata_decoder.h>

#include <cstring>
#include <string>

#include "wire/frame_codec.h"
#include "wire/vertex_id_runs.h"

namespace fq::wire::detail {
namespace {

template <class T>
bool expect(draco::DecoderBuffer& in, T want) {
  T v{};
  return in.Decode(&v) && v == want;
}

draco::DecoderBuffer buffer_at(std::string_view bytes, size_t at) {
  draco::DecoderBuffer in;
  in.Init(bytes.data(), bytes.size());
  in.StartDecodingFrom(int64_t(at));
  return in;
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
  return version && kind && in.Decode(&flags) && ((flags & METADATA_FLAG_MASK) != 0) == mesh;
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

/// Draco's raw sequential connectivity up to its indices: the counts, with Draco's own bounds
/// (MeshSequentialDecoder::DecodeConnectivity), and the "stored directly" byte.
bool read_connectivity_head(draco::DecoderBuffer& in, SequentialLayout& l) {
  if (!draco::DecodeVarint(&l.faces, &in) || !draco::DecodeVarint(&l.points, &in)) return false;
  const uint64_t faces = l.faces, points = l.points;
  if (faces > 0xffffffffull / 3 || faces > uint64_t(in.remaining_size()) / 3 || points > 3 * faces)
    return false;
  if (faces == 0 || !expect<uint8_t>(in, 1)) return false;  // 1: indices stored directly
  l.index_bytes = sequential_index_bytes(l.points);
  return true;
}

}  // namespace

bool read_sequential_layout(std::string_view bytes, SequentialLayout& l, std::vector<uint8_t>& runs) {
  draco::DecoderBuffer in = buffer_at(bytes, 0);
  l = SequentialLayout{};
  if (!read_header(in, true) || !read_metadata(in, runs, l.labelled) || !read_connectivity_head(in, l))
    return false;
  l.corners_at = size_t(in.decoded_size());
  return true;
}

bool sequential_corners_end(std::string_view bytes, const SequentialLayout& l, size_t& end) {
  const size_t corners = 3 * size_t(l.faces), room = bytes.size() - l.corners_at;
  if (l.index_bytes != 0) {
    if (room / l.index_bytes < corners) return false;
    end = l.corners_at + corners * l.index_bytes;
    return true;
  }
  // Varints: each ends at a byte below 0x80, after at most two bytes with the top bit set.
  const auto* p = reinterpret_cast<const uint8_t*>(bytes.data()) + l.corners_at;
  size_t seen = 0, k = 0;
  int run = 0;
  for (; k < room && seen < corners; ++k) {
    const bool more = (p[k] & 0x80) != 0;
    run = more ? run + 1 : 0;
    if (run == 3) return false;
    seen += more ? 0 : 1;
  }
  if (seen < corners) return false;
  end = l.corners_at + k;
  return true;
}

bool read_attribute_specs(std::string_view bytes, size_t at, bool labelled, size_t& values_at) {
  draco::DecoderBuffer in = buffer_at(bytes, at);
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
  if (!expect<uint8_t>(in, draco::SEQUENTIAL_ATTRIBUTE_ENCODER_QUANTIZATION) ||
      (labelled && !expect<uint8_t>(in, draco::SEQUENTIAL_ATTRIBUTE_ENCODER_INTEGER)))
    return false;
  values_at = size_t(in.decoded_size());
  return true;
}

bool plan_sequential_chunk(std::string_view bytes, uint32_t id_limit, SequentialPlan& plan,
                           std::vector<uint32_t>& ids) {
  std::vector<uint8_t> runs;
  return read_sequential_layout(bytes, plan.layout, runs) &&
         sequential_corners_end(bytes, plan.layout, plan.corners_end) &&
         read_attribute_specs(bytes, plan.corners_end, plan.layout.labelled, plan.values_at) &&
         decode_id_runs(runs.data(), runs.size(), plan.layout.points, id_limit, ids);
}

bool read_point_cloud_head(std::string_view bytes, uint32_t& n, size_t& specs_at) {
  draco::DecoderBuffer in = buffer_at(bytes, 0);
  int32_t points = 0;
  if (!read_header(in, false) || !in.Decode(&points) || points < 0) return false;
  // Draco reads the count as it is; a count no genuine chunk of this size could carry (a
  // forged one) is left to Draco's decoder and the caller's limits instead of sizing buffers.
  if (uint64_t(points) > 1024 * uint64_t(in.remaining_size())) return false;
  n = static_cast<uint32_t>(points);
  specs_at = size_t(in.decoded_size());
  return true;
}

}  // namespace fq::wire::detail
