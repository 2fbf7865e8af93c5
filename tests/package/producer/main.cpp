// What a third-party producer needs of fq, and only that: a mesh made in code becomes a frame
// (FrameHeader + Draco chunks) as fqd reads it, and the frame is read back the way fqd does
// (strict header parsing, chunk merge), so the bytes are checked, not only written.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/mesh_view.h"
#include "wire/frame_codec.h"
#include "wire/header_codec.h"

namespace {

// An n x n grid of quads on a wavy height field, two triangles each.
fq::Mesh wavy_grid(uint32_t n) {
  fq::Mesh m;
  for (uint32_t y = 0; y <= n; ++y) {
    for (uint32_t x = 0; x <= n; ++x) {
      m.positions.insert(m.positions.end(), {float(x), float(y), 0.3f * std::sin(0.7f * float(x + 2 * y))});
    }
  }
  for (uint32_t y = 0; y < n; ++y) {
    for (uint32_t x = 0; x < n; ++x) {
      const uint32_t v = y * (n + 1) + x;
      m.triangles.insert(m.triangles.end(), {v, v + 1, v + n + 1, v + 1, v + n + 2, v + n + 1});
    }
  }
  return m;
}

int fail(const char* what, const fq::Status& s) {
  std::fprintf(stderr, "fq_producer: %s: %s\n", what, s.message().c_str());
  return 1;
}

}  // namespace

int main() {
  const fq::Mesh mesh = wavy_grid(40);
  fq::wire::CodecOptions options;
  std::vector<std::string> chunks;
  if (fq::Status s = fq::wire::encode_frame(mesh.view(), nullptr, 4, options, chunks); !s.ok())
    return fail("encode", s);

  fq::wire::FrameHeader header;
  header.set_version(fq::wire::kWireVersion);
  header.set_stream_id("cam0");
  header.set_sequence(1);
  header.set_chunk_count(static_cast<uint32_t>(chunks.size()));
  header.set_vertex_count(mesh.num_vertices());
  header.mutable_params()->set_sigma_s(2.0f);
  const std::string header_bytes = header.SerializeAsString();

  fq::wire::FrameHeader parsed;
  if (fq::Status s = fq::wire::parse_frame_header(header_bytes, parsed); !s.ok()) return fail("header", s);
  std::vector<std::string_view> views(chunks.begin(), chunks.end());
  fq::Mesh decoded;
  if (fq::Status s = fq::wire::decode_frame(views, parsed.vertex_count(), options, decoded, nullptr); !s.ok())
    return fail("decode", s);
  // 16-bit quantization over a 40-unit box: a coordinate moves by at most 40 / 2^16 / 2.
  double worst = 0.0;
  for (size_t i = 0; i < mesh.positions.size(); ++i)
    worst = std::max(worst, double(std::abs(decoded.positions[i] - mesh.positions[i])));
  if (decoded.num_vertices() != mesh.num_vertices() || decoded.num_triangles() != mesh.num_triangles() ||
      worst > 1e-3) {
    std::fprintf(stderr, "fq_producer: the frame came back as %u vertices, %u triangles, off by %g\n",
                 decoded.num_vertices(), decoded.num_triangles(), worst);
    return 1;
  }
  std::printf("chunks %zu\nheader bytes %zu\nvertices %u\nround trip ok\n", chunks.size(),
              header_bytes.size(), decoded.num_vertices());
  return 0;
}
