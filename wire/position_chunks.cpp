// encode_positions / decode_positions: a frame's positions as Draco point clouds over
// contiguous vertex ranges (the POSITIONS result form; see docs/PROTOCOL.md).
#include <draco/compression/decode.h>
#include <draco/point_cloud/point_cloud.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <exception>
#include <string>

#include "core/mesh_checks.h"
#include "wire/draco_sequential.h"
#include "wire/draco_sequential_read.h"
#include "wire/frame_codec.h"
#include "wire/frame_split.h"

namespace fq::wire {
namespace {

fq::Status decode_range(std::string_view bytes, std::vector<float>& out) {
  draco::DecoderBuffer buf;
  buf.Init(bytes.data(), bytes.size());
  auto type = draco::Decoder::GetEncodedGeometryType(&buf);
  if (!type.ok()) return invalid_input("undecodable Draco data: " + type.status().error_msg_string());
  if (type.value() != draco::POINT_CLOUD)
    return invalid_input("a Draco triangle mesh, not a point cloud (a MESH-form result?)");
  draco::Decoder dec;
  auto pc = dec.DecodePointCloudFromBuffer(&buf);
  if (!pc.ok()) return invalid_input("undecodable Draco data: " + pc.status().error_msg_string());
  const draco::PointAttribute* pos = pc.value()->GetNamedAttribute(draco::GeometryAttribute::POSITION);
  if (pos == nullptr || pos->num_components() != 3) return invalid_input("no 3D position attribute");
  const uint32_t n = pc.value()->num_points();
  out.resize(3 * size_t(n));
  constexpr int64_t kPackedTriple = 3 * int64_t(sizeof(float));
  // What encode_positions gives: one copy, not a conversion per point.
  if (pos->is_mapping_identity() && pos->data_type() == draco::DT_FLOAT32 &&
      pos->byte_stride() == kPackedTriple && pos->size() >= n && n > 0) {
    std::memcpy(out.data(), pos->GetAddress(draco::AttributeValueIndex(0)), 3 * sizeof(float) * size_t(n));
    return {};
  }
  for (uint32_t p = 0; p < n; ++p) {
    if (!pos->ConvertValue<float>(pos->mapped_index(draco::PointIndex(p)), 3, &out[3 * size_t(p)]))
      return invalid_input("unreadable position of point " + std::to_string(p));
  }
  return {};
}

/// The chunks when every one is a point cloud as encode_positions writes it: each read
/// directly into its place in `out` (no draco::PointCloud, no copy to concatenate). False, with
/// `out` empty, when any is not; Draco's decoder then reads them all.
bool read_own(const std::vector<std::string_view>& chunks, uint32_t vertex_count, const CodecOptions& options,
              std::vector<float>& out) {
  std::vector<size_t> first(chunks.size() + 1, 0);
  for (size_t i = 0; i < chunks.size(); ++i) {
    uint32_t n = 0;
    if (!detail::sequential_point_count(chunks[i], n)) return false;
    first[i + 1] = first[i] + n;
  }
  if (first.back() == 0 || (vertex_count != 0 && first.back() != vertex_count)) return false;
  out.resize(3 * first.back());
  std::vector<uint8_t> ok(chunks.size(), 0);
  detail::for_each_chunk(chunks.size(), options.threads, [&](size_t i, size_t) {
    const auto n = static_cast<uint32_t>(first[i + 1] - first[i]);
    try {
      const auto scratch = detail::sequential_scratch().borrow();
      ok[i] =
          detail::read_sequential_point_cloud(chunks[i], n, out.data() + 3 * first[i], scratch->quantized);
    } catch (const std::exception&) {  // bad_alloc: Draco's decoder gets the chunks instead
      ok[i] = 0;
    }
  });
  if (std::find(ok.begin(), ok.end(), uint8_t{0}) == ok.end()) return true;
  out.clear();
  return false;
}

}  // namespace

fq::Status encode_positions(const float* positions, uint32_t num_vertices, uint32_t chunks,
                            const CodecOptions& options, std::vector<std::string>& out) {
  out.clear();
  if (options.position_bits < 1 || options.position_bits > 30 || options.encode_speed < 0 ||
      options.encode_speed > 10 || options.decode_speed < 0 || options.decode_speed > 10 ||
      options.threads < 1)
    return invalid_argument("bad codec options (position_bits 1..30, speeds 0..10, threads >= 1)");
  if (chunks == 0 || chunks > kMaxChunks)
    return invalid_argument("chunk count " + std::to_string(chunks) + " outside [1, " +
                            std::to_string(kMaxChunks) + "]");
  if (num_vertices == 0) return invalid_input("no vertices");
  // One pass on the codec threads gives the box and checks the coordinates (on a 4M-vertex
  // frame a serial pass cost as much as a chunk's encode); a second names a fault.
  bool finite = false;
  const detail::Box box =
      detail::bounding_box(fq::MeshView{positions, num_vertices, nullptr, 0}, options.threads, &finite);
  if (!finite) {
    const uint64_t floats = 3 * uint64_t(num_vertices);
    const uint64_t k = first_non_finite(positions, floats, options.threads);
    if (k == floats) return {fq::StatusCode::kInternal, "finiteness check disagrees with the box pass"};
    return invalid_input("vertex " + std::to_string(k / 3) + " has a non-finite coordinate");
  }
  const uint32_t parts = std::min(chunks, num_vertices);
  std::vector<std::string> encoded(parts);
  std::vector<fq::Status> status(parts);
  detail::for_each_chunk(parts, options.threads, [&](size_t i, size_t) {
    const auto first = static_cast<uint32_t>(uint64_t(num_vertices) * i / parts);
    const auto last = static_cast<uint32_t>(uint64_t(num_vertices) * (i + 1) / parts);
    try {
      // Vertices [first, last) as a point cloud, POSITION only: Draco's sequential point cloud
      // coder keeps them in vertex order (its k-d tree coder, which Draco picks for quantized
      // clouds below speed 10, would reorder them), written directly (draco_sequential.h).
      const auto scratch = detail::sequential_scratch().borrow();
      status[i] = detail::write_point_cloud(positions + 3 * size_t(first), last - first, options, box,
                                            *scratch, encoded[i]);
    } catch (const std::exception& e) {  // bad_alloc: a fault of this frame, not of the process
      status[i] = {fq::StatusCode::kInternal, std::string("encoding failed: ") + e.what()};
    }
  });
  for (size_t i = 0; i < parts; ++i) {
    if (!status[i].ok()) return {status[i].code(), "chunk " + std::to_string(i) + ": " + status[i].message()};
  }
  out = std::move(encoded);
  return {};
}

fq::Status decode_positions(const std::vector<std::string_view>& chunks, uint32_t vertex_count,
                            const CodecOptions& options, std::vector<float>& out) {
  out.clear();
  if (chunks.empty()) return invalid_input("frame has no Draco chunks");
  if (chunks.size() > kMaxChunks)
    return invalid_input("frame has more than " + std::to_string(kMaxChunks) + " chunks");
  if (read_own(chunks, vertex_count, options, out)) return {};
  std::vector<std::vector<float>> parts(chunks.size());
  std::vector<fq::Status> status(chunks.size());
  detail::for_each_chunk(chunks.size(), options.threads, [&](size_t i, size_t) {
    try {
      status[i] = decode_range(chunks[i], parts[i]);
    } catch (const std::exception& e) {  // bad_alloc on a forged chunk: this frame fails
      status[i] = invalid_input(std::string("decoding failed: ") + e.what());
    }
  });
  size_t floats = 0;
  for (size_t i = 0; i < parts.size(); ++i) {
    if (!status[i].ok()) return invalid_input("chunk " + std::to_string(i) + ": " + status[i].message());
    floats += parts[i].size();
  }
  if (vertex_count != 0 && floats != 3 * size_t(vertex_count))
    return invalid_input("chunks carry " + std::to_string(floats / 3) + " points, the frame has " +
                         std::to_string(vertex_count) + " vertices");
  out.reserve(floats);
  for (const auto& p : parts) out.insert(out.end(), p.begin(), p.end());
  return {};
}

}  // namespace fq::wire
