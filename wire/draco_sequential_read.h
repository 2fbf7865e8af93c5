// Reading the frame codec's own sequential chunks (and POSITIONS point clouds) without a
// draco::Mesh or draco::PointCloud.
//
// decode_frame gets chunks from anyone: any Draco mesh is accepted and decoded by Draco. The
// chunks fq itself writes (write_sequential_chunk: Draco's sequential coder, quantized
// positions, optional "fq_label", ids as runs) are read here instead: the header fields are
// parsed, the values entropy-decoded by Draco's own symbol decoder (draco::DecodeSymbols), and
// the corrections, the wrap and the dequantization are one pass that computes exactly what
// Draco's decoder computes. This skips Draco's copy of the faces into a mesh, its integer and
// float attribute buffers and the passes between them. Anything that is not exactly that
// layout, or fails a check on the way, is left to Draco's decoder, which has the last word:
// this reader never accepts a chunk Draco would refuse, and never reads one differently
// (tests/wire/draco_sequential_read_test.cpp compares both on the same bytes).
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

namespace fq::wire::detail {

/// A sequential chunk as read by read_sequential_chunk.
struct SequentialChunk {
  uint32_t points = 0;
  uint32_t faces = 0;
  std::vector<uint32_t> corners;  ///< 3 point indices a face, each below `points`
  std::vector<float> positions;   ///< 3 a point, as Draco's decoder dequantizes them
  std::vector<uint32_t> ids;      ///< global vertex id a point (the chunk's id runs)
  std::vector<uint32_t> labels;   ///< "fq_label" a point; empty when the chunk has none
  std::vector<int32_t> values;    ///< scratch: the quantized positions
};

/// Reads `bytes` into `out` when they are a triangle mesh in the layout write_sequential_chunk
/// writes and decode without fault; false otherwise (hand them to Draco's decoder then). Ids
/// must be below `id_limit` and faces must name existing points, as decode_frame requires.
/// `out`'s buffers keep their capacity across calls.
bool read_sequential_chunk(std::string_view bytes, uint32_t id_limit, SequentialChunk& out);

/// The point count of a POSITIONS point cloud as write_point_cloud writes it (Draco's sequential
/// point cloud header), or false when `bytes` do not start that way.
bool sequential_point_count(std::string_view bytes, uint32_t& n);

/// Reads such a point cloud of `n` points (sequential_point_count) into out[0, 3 n), as
/// Draco's decoder dequantizes them; false when the bytes are not exactly that layout or fail
/// a check (hand them to Draco's decoder then). `values` is scratch.
bool read_sequential_point_cloud(std::string_view bytes, uint32_t n, float* out,
                                 std::vector<int32_t>& values);

}  // namespace fq::wire::detail
