// The floor of the frame codec: what a chunked codec built on Draco's own coder pays, namely
// draco::Encoder and draco::Decoder on the frame's chunks as draco::Mesh objects, positions
// only, one task per chunk. fqbench --codec sets fq's codec beside it; fqstreambench sets fqd's
// host CPU per frame beside its decode + encode.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/mesh_view.h"
#include "wire/frame_codec.h"
#include "wire/frame_split.h"

namespace draco {
class Mesh;
}

namespace fq::client {

/// The frame's chunks as position-only Draco meshes: the same split and points as
/// wire::encode_frame. Built once, untimed: the floor leaves out what fq adds around Draco
/// (input checks, the split, the ids, reading the decoded meshes back and merging them).
struct FloorChunks {
  FloorChunks();
  FloorChunks(FloorChunks&&) noexcept;
  ~FloorChunks();
  wire::detail::Box box;
  std::vector<std::unique_ptr<draco::Mesh>> meshes;
  std::vector<uint8_t> sequential;  ///< per chunk: coded with Draco's sequential coder
};

FloorChunks floor_chunks(const MeshView& mesh, uint32_t chunks, const wire::CodecOptions& opt);
/// Draco's encoder on every chunk into `out`; false when one fails.
bool floor_encode(const FloorChunks& f, const wire::CodecOptions& opt, std::vector<std::string>& out);
/// Draco's decoder on every encoded chunk; false when one fails.
bool floor_decode(const std::vector<std::string>& encoded, int threads);

/// Median CPU ms over `rounds` of the floor's encode and decode of `mesh` cut in `chunks`
/// (the threads that help included, common/thread_cpu.h); negative when the floor failed.
struct FloorCpu {
  double encode_ms = -1, decode_ms = -1;
};
FloorCpu floor_cpu(const MeshView& mesh, uint32_t chunks, const wire::CodecOptions& opt, int rounds);

}  // namespace fq::client
