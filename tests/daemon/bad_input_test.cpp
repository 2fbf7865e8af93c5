// Every kind of bad frame from an authenticated (CURVE) producer gets an ERROR result on its
// stream's topic, is counted, and the next good frame of the stream is served. (From a producer
// without CURVE, malformed and undecodable ones are refused instead: stream_exposure_test.cpp.)
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>

#include "tests/daemon/daemon_harness.h"
#include "tests/daemon/draco_plain.h"
#include "tests/daemon/test_keys.h"
#include "tests/support/test_meshes.h"
#include "tests/wire/wire_test_meshes.h"
#include "wire/header_codec.h"

namespace fq::test {
namespace {

struct BadCase {
  const char* name;
  const char* expect_in_error;  ///< words the error message must contain one of, '|'-separated
  std::function<std::vector<std::string>(const Mesh&)> make;
};

std::vector<std::string> good_parts(const Mesh& m, uint32_t chunks = 1) {
  client::FrameSpec spec;
  spec.stream_id = "cam";
  spec.chunks = chunks;
  std::vector<std::string> parts;
  EXPECT_TRUE(client::build_frame(m.view(), spec, 0, parts).ok());
  return parts;
}

// Rewrites the header of built parts.
std::vector<std::string> with_header(std::vector<std::string> parts,
                                     const std::function<void(wire::FrameHeader&)>& f) {
  wire::FrameHeader h;
  EXPECT_TRUE(h.ParseFromString(parts[1]));
  f(h);
  parts[1] = h.SerializeAsString();
  return parts;
}

// A good header around one plain Draco payload (vertex count taken from it).
std::vector<std::string> plain_frame(const Mesh& m, std::string payload) {
  std::vector<std::string> parts =
      with_header(good_parts(m), [](wire::FrameHeader& h) { h.set_vertex_count(0); });
  parts[2] = std::move(payload);
  return parts;
}

const std::vector<BadCase>& bad_cases() {
  static const std::vector<BadCase> cases = {
      {"undecodable payload", "Draco", [](const Mesh& m) { return plain_frame(m, std::string(200, 'x')); }},
      {"truncated payload", "chunk",
       [](const Mesh& m) {
         auto p = good_parts(m);
         p[2].resize(p[2].size() / 2);
         return p;
       }},
      {"wrong version", "version",
       [](const Mesh& m) {
         return with_header(good_parts(m), [](auto& h) { h.set_version(wire::kWireVersion + 1); });
       }},
      {"unknown field", "unknown field",
       [](const Mesh& m) {
         auto p = good_parts(m);
         p[1] += std::string("\xa0\x06\x01", 3);  // field 100, varint 1
         return p;
       }},
      {"unparsable header", "frame header",
       [](const Mesh& m) {
         auto p = good_parts(m);
         p[1] = "\xff\xff\xff";
         return p;
       }},
      {"NaN coordinates", "finite",
       [](const Mesh& m) {
         Mesh bad = m;
         bad.positions[4] = std::numeric_limits<float>::quiet_NaN();
         return plain_frame(m, draco_plain_mesh(bad));
       }},
      {"out-of-range vertex ids", "out of range",
       [](const Mesh& m) { return with_header(good_parts(m), [](auto& h) { h.set_vertex_count(10); }); }},
      // Draco itself refuses to decode a mesh without faces, so either message is right.
      {"zero faces", "faces|undecodable",
       [](const Mesh& m) {
         Mesh none = m;
         none.triangles.clear();
         return plain_frame(m, draco_plain_mesh(none));
       }},
      {"point cloud", "point cloud", [](const Mesh& m) { return plain_frame(m, draco_point_cloud(m)); }},
      {"over the vertex cap", "cap", [](const Mesh&) { return good_parts(make_icosphere(4, 1.0f)); }},
      // Every part under the cap (a larger part is refused at the socket: see
      // admission_test.cpp), the whole message over it.
      {"over the byte cap", "bytes",
       [](const Mesh& m) {
         auto p = good_parts(m);
         for (int i = 0; i < 3; ++i) p.push_back(std::string(60'000, '\0'));
         return p;
       }},
      {"decode bomb", "declares",
       [](const Mesh& m) {
         auto p = good_parts(m);
         p[2] = test_wire::forge_face_count(p[2], 300'000'000);
         return p;
       }},
      {"invalid parameters", "theta",
       [](const Mesh& m) {
         return with_header(good_parts(m), [](wire::FrameHeader& h) {
           h.mutable_params()->set_theta(2.0f);
           h.set_compute(wire::FILTER_AND_CLUSTER);
         });
       }},
      {"wrong part count", "chunk",
       [](const Mesh& m) { return with_header(good_parts(m), [](auto& h) { h.set_chunk_count(2); }); }},
      {"no chunk at all", "part",
       [](const Mesh& m) {
         auto p = good_parts(m);
         p.resize(2);
         return p;
       }},
      {"topic and header disagree", "topic",
       [](const Mesh& m) { return with_header(good_parts(m), [](auto& h) { h.set_stream_id("other"); }); }},
  };
  return cases;
}

bool mentions_one_of(const std::string& message, const std::string& words) {
  size_t start = 0;
  for (;;) {
    const size_t bar = words.find('|', start);
    if (message.find(words.substr(start, bar - start)) != std::string::npos) return true;
    if (bar == std::string::npos) return false;
    start = bar + 1;
  }
}

TEST(DaemonBadInput, EveryBadFrameGetsAnErrorResultAndTheNextFrameIsServed) {
  daemon::DaemonConfig c = test_config();
  c.caps.max_vertices = 2000;        // the 642-vertex sphere passes, a 2562-vertex one does not
  c.caps.max_frame_bytes = 100'000;  // so does its ~10 KB frame, a 200 KB one does not
  const TestKeys keys;
  DaemonHarness h(keys.secured(c), {keys.server_pub, keys.client_key});
  const Mesh mesh = noisy_sphere();
  uint64_t errors = 0;
  for (const BadCase& bad : bad_cases()) {
    SCOPED_TRACE(bad.name);
    h.send_parts(bad.make(mesh));
    const client::ReceivedResult e = h.receive("cam");
    EXPECT_EQ(e.header.status(), wire::ERROR) << bad.name;
    EXPECT_FALSE(e.header.error().empty());
    EXPECT_TRUE(mentions_one_of(e.header.error(), bad.expect_in_error)) << e.header.error();
    EXPECT_TRUE(e.chunks.empty());
    ++errors;
    h.send_parts(good_parts(mesh));
    const client::ReceivedResult ok = h.receive_decoded("cam");
    EXPECT_EQ(ok.header.status(), wire::OK);
    EXPECT_EQ(ok.mesh.num_vertices(), mesh.num_vertices());
  }
  const wire::StreamCounters k = h.counters("cam");
  EXPECT_EQ(k.errors(), errors);
  EXPECT_EQ(k.frames_out(), errors);
  EXPECT_EQ(k.frames_in(), 2 * errors);
}

TEST(DaemonBadInput, APlainDracoMeshFromAnyProducerIsAValidFrame) {
  daemon::DaemonConfig c = test_config();
  c.defaults.output.form = daemon::ResultForm::kMesh;  // results that carry their own faces
  DaemonHarness h(c);
  const Mesh mesh = noisy_sphere();
  h.send_parts(plain_frame(mesh, draco_plain_mesh(mesh)));
  const client::ReceivedResult r = h.receive_decoded("cam");
  EXPECT_EQ(r.header.status(), wire::OK);
  EXPECT_EQ(r.mesh.num_vertices(), mesh.num_vertices());
  EXPECT_EQ(r.mesh.num_triangles(), mesh.num_triangles());
}

}  // namespace
}  // namespace fq::test
