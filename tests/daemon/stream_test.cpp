// fqd over real sockets: frames in, results out, per-stream and run-time parameters,
// chunked frames.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <random>

#include "clients/common/frame_sender.h"
#include "core/parallel_for.h"
#include "kernels/cpu_engine.h"
#include "tests/daemon/daemon_harness.h"
#include "tests/support/test_meshes.h"
#include "wire/frame_codec.h"

namespace fq::test {
namespace {

// What fqd should publish for `mesh` under `params`: the same Draco round trips around
// the same engine (the CPU engine gives the same result whatever its thread count).
wire::CodecOptions codec_options() {
  wire::CodecOptions opt;  // the producer's and fqd's default Draco settings
  opt.encode_speed = client::FrameSpec{}.encode_speed;
  opt.decode_speed = client::FrameSpec{}.decode_speed;
  return opt;
}

// `mesh` as fqd decodes it from a producer's frame.
Mesh seen_by_fqd(const Mesh& mesh) {
  std::vector<std::string> chunks;
  EXPECT_TRUE(wire::encode_frame(mesh.view(), nullptr, 1, codec_options(), chunks).ok());
  Mesh seen;
  EXPECT_TRUE(wire::decode_frame({chunks[0]}, mesh.num_vertices(), codec_options(), seen, nullptr).ok());
  return seen;
}

std::vector<float> expected_positions(const Mesh& mesh, const Params& params) {
  const wire::CodecOptions opt = codec_options();
  std::vector<std::string> chunks;
  const Mesh seen = seen_by_fqd(mesh);
  CpuEngine engine(1);
  FrameResult result;
  EXPECT_TRUE(engine.process(seen.view(), params, result).ok());
  const MeshView out_view{result.positions.data(), seen.num_vertices(), seen.triangles.data(),
                          seen.num_triangles()};
  EXPECT_TRUE(wire::encode_frame(out_view, nullptr, 1, opt, chunks).ok());
  Mesh published;
  EXPECT_TRUE(wire::decode_frame({chunks[0]}, mesh.num_vertices(), opt, published, nullptr).ok());
  return published.positions;
}

// The triangles as a sorted list, each rotated to start at its smallest index.
std::vector<std::array<uint32_t, 3>> canonical_triangles(const Mesh& m) {
  std::vector<std::array<uint32_t, 3>> out;
  for (uint32_t f = 0; f < m.num_triangles(); ++f) {
    std::array<uint32_t, 3> t{m.triangles[3 * f], m.triangles[3 * f + 1], m.triangles[3 * f + 2]};
    while (t[0] > t[1] || t[0] > t[2]) t = {t[1], t[2], t[0]};
    out.push_back(t);
  }
  std::sort(out.begin(), out.end());
  return out;
}

client::FrameSpec spec_for(const std::string& stream, uint32_t chunks = 1) {
  client::FrameSpec s;
  s.stream_id = stream;
  s.chunks = chunks;
  return s;
}

TEST(DaemonStream, NFramesInGiveNResultsInOrderWithCorrectCounts) {
  DaemonHarness h;
  const Mesh mesh = noisy_sphere();
  constexpr uint64_t kFrames = 5;
  for (uint64_t i = 0; i < kFrames; ++i) {
    h.send(mesh, spec_for("cam"), 100 + i);
    const client::ReceivedResult r = h.receive_decoded("cam", &mesh);
    EXPECT_EQ(r.header.sequence(), 100 + i);
    EXPECT_EQ(r.header.form(), wire::POSITIONS);  // the default
    EXPECT_EQ(r.header.status(), wire::OK);
    EXPECT_EQ(r.mesh.num_vertices(), mesh.num_vertices());
    EXPECT_EQ(r.mesh.num_triangles(), mesh.num_triangles());
    EXPECT_TRUE(all_finite(r.mesh.positions));
    EXPECT_GT(r.header.cluster_count(), 0u);
    EXPECT_EQ(r.labels.size(), mesh.num_vertices());
    EXPECT_EQ(r.header.engine(), "cpu");
    EXPECT_GT(r.header.latency_ms(), 0.0);

    bool has_decode = false, has_engine = false, has_encode = false, has_send = false;
    for (const wire::StageTiming& t : r.header.timings()) {
      has_decode |= t.name() == "decode";
      has_engine |= t.name() == "engine";
      has_encode |= t.name() == "encode";
      if (t.name() == "send_to_publish") {
        has_send = true;
        EXPECT_GE(t.ms(), r.header.latency_ms());  // sent before fqd received it
      }
    }
    EXPECT_TRUE(has_decode && has_engine && has_encode && has_send);
  }
  const wire::StreamCounters c = h.counters("cam");
  EXPECT_EQ(c.frames_in(), kFrames);
  EXPECT_EQ(c.frames_out(), kFrames);
  EXPECT_EQ(c.errors() + c.superseded() + c.dropped_stale(), 0u);
}

TEST(DaemonStream, ResultMatchesTheEngineOnTheDecodedFrame) {
  DaemonHarness h;
  const Mesh mesh = noisy_sphere(3);
  h.send(mesh, spec_for("cam"), 0);
  const client::ReceivedResult r = h.receive_decoded("cam");
  Params p = test_config().defaults.params;
  const std::vector<float> want = expected_positions(mesh, p);
  EXPECT_LT(max_displacement(r.mesh.positions, want), 1e-6);
  EXPECT_GT(max_displacement(r.mesh.positions, mesh.positions), 1e-3) << "the filter moved nothing";
  // The noise "qf+" estimated and filtered for travels in the header, as the engine finds it on
  // the frame before the wire's quantization (within 0.1 %).
  CpuEngine engine(2);
  FrameResult direct;
  ASSERT_TRUE(engine.process(mesh.view(), p, direct).ok());
  EXPECT_GT(r.header.noise_estimate(), 0.f);
  EXPECT_NEAR(r.header.noise_estimate(), direct.noise_estimate, 1e-3f * direct.noise_estimate);
  EXPECT_EQ(r.header.filter_noise(), r.header.noise_estimate());
}

TEST(DaemonStream, TwoStreamsWithDifferentParametersGiveDifferentResults) {
  daemon::DaemonConfig c = test_config();
  c.streams["soft"] = c.defaults;
  c.streams["soft"].params.filtering.refine.strength = 0.5f;
  c.streams["strong"] = c.defaults;
  c.streams["strong"].params.filtering.refine.strength = 3.0f;
  DaemonHarness h(c);
  const Mesh mesh = noisy_sphere();
  h.send(mesh, spec_for("soft"), 0);
  h.send(mesh, spec_for("strong"), 0);
  const client::ReceivedResult soft = h.receive_decoded("soft");
  const client::ReceivedResult strong = h.receive_decoded("strong");
  Params ps = c.streams["soft"].params, pg = c.streams["strong"].params;
  EXPECT_LT(max_displacement(soft.mesh.positions, expected_positions(mesh, ps)), 1e-6);
  EXPECT_LT(max_displacement(strong.mesh.positions, expected_positions(mesh, pg)), 1e-6);
  EXPECT_GT(max_displacement(soft.mesh.positions, strong.mesh.positions), 1e-3);
}

// A stream with temporal > 0: each frame after the first is filtered with the stream's last
// result (track A here: the frames keep their connectivity), as a CPU engine with a history gives
// on the same decoded frames; a frame far from the last one with other triangles is a scene cut
// for track B, counted, and filtered alone.
TEST(DaemonStream, TemporalStreamFollowsItsHistoryAndCountsSceneCuts) {
  daemon::DaemonConfig c = test_config();
  c.defaults.params.cluster = false;
  c.streams["still"] = c.defaults;
  c.streams["still"].params.filtering.temporal = 0.75f;
  DaemonHarness h(c);
  const Params p = c.streams["still"].params;
  Params alone = p;
  alone.filtering.temporal = 0.f;
  // The engine fqd runs, replayed on the frames as fqd decodes them.
  CpuEngine replay(1);
  TemporalHistory history;
  replay.set_history(&history);
  Mesh far = noisy_sphere(40);
  for (size_t i = 0; i < far.positions.size(); i += 3) far.positions[i] += 20.f;
  // The first triangle's corners turned: the same surface, another triangle array (with the
  // connectivity kept, track A would follow the jump as a motion of its ids).
  std::rotate(far.triangles.begin(), far.triangles.begin() + 1, far.triangles.begin() + 3);
  const std::vector<Mesh> frames = {noisy_sphere(31), noisy_sphere(32), noisy_sphere(33), far};
  for (uint64_t i = 0; i < frames.size(); ++i) {
    h.send(frames[i], spec_for("still"), i);
    const client::ReceivedResult r = h.receive_decoded("still", &frames[i]);
    ASSERT_EQ(r.header.status(), wire::OK) << r.header.error();
    FrameResult want;
    ASSERT_TRUE(replay.process(seen_by_fqd(frames[i]).view(), p, want).ok());
    EXPECT_LT(max_displacement(r.mesh.positions, want.positions), 1e-4) << "frame " << i;
    const double from_alone = max_displacement(r.mesh.positions, expected_positions(frames[i], alone));
    if (i == 0 || i == 3)
      EXPECT_LT(from_alone, 1e-6) << "frame " << i << " has no history to follow";
    else
      EXPECT_GT(from_alone, 1e-4) << "frame " << i << " followed nothing";
  }
  EXPECT_EQ(history.resets, 1u);
  EXPECT_EQ(h.counters("still").temporal_resets(), 1u);
}

// A frame with the last frame's triangles whose vertex ids no longer follow the surface (every
// position handed to another id) is refused by track A: it runs track B, the result header says
// so, and the stream counts it; frames whose ids follow a smooth motion are not counted.
TEST(DaemonStream, RefusedVertexIdsAreCountedPerStream) {
  daemon::DaemonConfig c = test_config();
  c.defaults.params.cluster = false;
  c.streams["ids"] = c.defaults;
  c.streams["ids"].params.filtering.temporal = 0.75f;
  DaemonHarness h(c);
  Mesh scrambled = noisy_sphere(43);
  std::vector<uint32_t> order(scrambled.num_vertices());
  for (uint32_t v = 0; v < order.size(); ++v) order[v] = v;
  std::shuffle(order.begin(), order.end(), std::mt19937(7));
  const Mesh kept = scrambled;
  for (uint32_t v = 0; v < order.size(); ++v)
    for (int k = 0; k < 3; ++k)
      scrambled.positions[3 * size_t(v) + k] = kept.positions[3 * size_t(order[v]) + k];
  const std::vector<Mesh> frames = {noisy_sphere(41), noisy_sphere(42), scrambled};
  // The first frame has nothing to follow: track B, with no history.
  const std::array<wire::TemporalTrack, 3> tracks = {wire::TEMPORAL_SPACE, wire::TEMPORAL_IDS,
                                                     wire::TEMPORAL_SPACE};
  for (uint64_t i = 0; i < frames.size(); ++i) {
    h.send(frames[i], spec_for("ids"), i);
    const client::ReceivedResult r = h.receive("ids");
    ASSERT_EQ(r.header.status(), wire::OK) << r.header.error();
    EXPECT_EQ(r.header.temporal_track(), tracks[i]) << "frame " << i;
    EXPECT_EQ(h.counters("ids").ids_refused(), i == 2 ? 1u : 0u) << "frame " << i;
  }
}

TEST(DaemonStream, RuntimeParameterChangeTakesEffectOnTheNextFrame) {
  DaemonHarness h;
  const Mesh mesh = noisy_sphere();
  h.send(mesh, spec_for("cam"), 0);
  const client::ReceivedResult before = h.receive_decoded("cam");

  wire::ControlRequest set;
  set.mutable_set_params()->set_stream_id("cam");
  set.mutable_set_params()->mutable_params()->set_sigma_s(4.0f);
  set.mutable_set_params()->mutable_params()->set_strength(3.0f);
  set.mutable_set_params()->set_compute(wire::FILTER);
  const wire::ControlReply sr = h.control(set);
  ASSERT_TRUE(sr.ok()) << sr.error();
  EXPECT_FLOAT_EQ(sr.params().sigma_s(), 4.0f);
  EXPECT_FLOAT_EQ(sr.params().strength(), 3.0f);

  wire::ControlRequest get;
  get.mutable_get_params()->set_stream_id("cam");
  const wire::ControlReply gr = h.control(get);
  ASSERT_TRUE(gr.ok()) << gr.error();
  EXPECT_FLOAT_EQ(gr.params().sigma_s(), 4.0f);
  EXPECT_EQ(gr.compute(), wire::FILTER);

  h.send(mesh, spec_for("cam"), 1);
  const client::ReceivedResult after = h.receive_decoded("cam");
  Params p = test_config().defaults.params;
  p.filtering.sigma_s = 4.0f;
  p.filtering.refine.strength = 3.0f;
  p.cluster = false;
  EXPECT_LT(max_displacement(after.mesh.positions, expected_positions(mesh, p)), 1e-6);
  EXPECT_GT(max_displacement(after.mesh.positions, before.mesh.positions), 1e-3);
  EXPECT_EQ(after.header.cluster_count(), 0u);
  EXPECT_TRUE(after.labels.empty());
}

TEST(DaemonStream, InvalidRuntimeParametersAreRejectedAndKeepTheOldOnes) {
  DaemonHarness h;
  wire::ControlRequest set;
  set.mutable_set_params()->set_stream_id("cam");
  set.mutable_set_params()->set_create(true);
  set.mutable_set_params()->mutable_params()->set_theta(1.5f);
  const wire::ControlReply r = h.control(set);
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.error().find("theta"), std::string::npos) << r.error();
  wire::ControlRequest get;
  get.mutable_get_params()->set_stream_id("cam");
  const wire::ControlReply g = h.control(get);
  ASSERT_TRUE(g.ok()) << g.error();
  EXPECT_FLOAT_EQ(g.params().theta(), test_config().defaults.params.clustering.theta);
  wire::ControlRequest unknown;
  unknown.mutable_get_params()->set_stream_id("nobody");
  EXPECT_FALSE(h.control(unknown).ok());
}

TEST(DaemonStream, ChunkedAndUnchunkedFramesGiveTheSameResult) {
  daemon::DaemonConfig c = test_config();
  c.defaults.output.form = daemon::ResultForm::kMesh;  // results that carry their own faces
  DaemonHarness h(c);
  const Mesh mesh = noisy_sphere(11);
  h.send(mesh, spec_for("one", 1), 0);
  h.send(mesh, spec_for("four", 4), 0);
  const client::ReceivedResult one = h.receive_decoded("one");
  const client::ReceivedResult four = h.receive_decoded("four");
  EXPECT_EQ(one.header.chunk_count(), 1u);
  EXPECT_EQ(four.header.chunk_count(), 4u);  // output chunks "same as input"
  // Chunks arrive with their triangles in another order, so the engine sums the same
  // terms in another order (the noise estimate's fits visit their rings in triangle order,
  // and every pass follows the estimate): equal up to float rounding and a few quantization
  // steps (measured 1.1e-4 on a unit sphere).
  EXPECT_LT(max_displacement(one.mesh.positions, four.mesh.positions), 2e-4);
  EXPECT_EQ(one.labels, four.labels);
  // Chunking may reorder the triangles (and rotate their corners), not change them.
  EXPECT_EQ(canonical_triangles(one.mesh), canonical_triangles(four.mesh));
  EXPECT_EQ(one.header.cluster_count(), four.header.cluster_count());
}

TEST(DaemonStream, AMeshResultIsCutAsItsInputWas) {
  daemon::DaemonConfig c = test_config();
  c.defaults.output.form = daemon::ResultForm::kMesh;
  DaemonHarness h(c);
  const Mesh mesh = noisy_sphere(7);
  // Uneven input chunks, which no split of fqd's own would make (its chunks are equal).
  const uint32_t f = mesh.num_triangles();
  const std::vector<uint32_t> counts{f / 10, f / 3, f - f / 10 - f / 3};
  std::vector<std::string> parts;
  ASSERT_TRUE(client::build_frame(mesh.view(), spec_for("uneven", 3), 0, parts).ok());
  std::vector<std::string> chunks;
  ASSERT_TRUE(wire::encode_frame_as(mesh.view(), nullptr, counts, wire::CodecOptions{}, chunks).ok());
  ASSERT_EQ(parts.size(), 2 + chunks.size());
  std::copy(chunks.begin(), chunks.end(), parts.begin() + 2);
  h.send_parts(parts);
  const client::ReceivedResult r = h.receive_decoded("uneven");
  ASSERT_EQ(r.header.form(), wire::MESH);
  std::vector<std::string_view> views;
  for (const zmq::message_t& m : r.chunks) views.emplace_back(m.data<char>(), m.size());
  Mesh back;
  std::vector<uint32_t> result_counts;
  ASSERT_TRUE(
      wire::decode_frame(views, mesh.num_vertices(), wire::CodecOptions{}, back, nullptr, &result_counts)
          .ok());
  EXPECT_EQ(result_counts, counts);
  EXPECT_EQ(canonical_triangles(back), canonical_triangles(mesh));
}

TEST(DaemonStream, ALargePositionsResultIsCutForMoreCores) {
  daemon::DaemonConfig c = test_config();
  c.streams["big"] = c.defaults;  // output chunks "same": POSITIONS may take more
  c.streams["one"] = c.defaults;
  c.streams["one"].output.chunks = 1;
  DaemonHarness h(c);
  const Mesh mesh = noisy_sphere(9, 6);  // 40,962 vertices: two chunks of at least 16,384
  // One after the other: sent together on a loaded machine, the light stream's wait could
  // make the engine preempt the big frame (engine-time fairness), which then never comes out.
  h.send(mesh, spec_for("big", 1), 0);
  const client::ReceivedResult big = h.receive_decoded("big", &mesh);
  h.send(mesh, spec_for("one", 1), 0);
  const client::ReceivedResult one = h.receive_decoded("one", &mesh);
  ASSERT_EQ(big.header.form(), wire::POSITIONS);
  const uint32_t cores = static_cast<uint32_t>(hardware_threads());
  EXPECT_EQ(big.header.chunk_count(), std::max(1u, std::min(cores, mesh.num_vertices() / 16384)));
  EXPECT_EQ(one.header.chunk_count(), 1u);
  EXPECT_EQ(big.mesh.positions, one.mesh.positions);  // vertex ranges of one grid, concatenated
}

TEST(DaemonStream, BothResultFormsCarryTheSamePositionsAndLabels) {
  daemon::DaemonConfig c = test_config();
  c.streams["p"] = c.defaults;
  c.streams["m"] = c.defaults;
  c.streams["m"].output.form = daemon::ResultForm::kMesh;
  DaemonHarness h(c);
  const Mesh mesh = noisy_sphere(5);
  h.send(mesh, spec_for("p", 3), 0);
  h.send(mesh, spec_for("m", 3), 0);
  const client::ReceivedResult p = h.receive_decoded("p", &mesh);
  const client::ReceivedResult m = h.receive_decoded("m");
  EXPECT_EQ(p.header.form(), wire::POSITIONS);
  EXPECT_EQ(m.header.form(), wire::MESH);
  EXPECT_EQ(p.header.chunk_count(), 3u);
  EXPECT_EQ(p.mesh.positions, m.mesh.positions);  // one quantization grid in both forms
  EXPECT_EQ(p.mesh.triangles, mesh.triangles);
  EXPECT_EQ(canonical_triangles(m.mesh), canonical_triangles(mesh));
  ASSERT_EQ(p.header.labels_size(), static_cast<int>(mesh.num_vertices()));
  EXPECT_EQ(p.labels, m.labels);
  size_t positions_bytes = 0, mesh_bytes = 0;
  for (const auto& chunk : p.chunks) positions_bytes += chunk.size();
  for (const auto& chunk : m.chunks) mesh_bytes += chunk.size();
  EXPECT_LT(positions_bytes, mesh_bytes) << "the positions form carries no connectivity";

  // A consumer that needs the faces asks for the mesh form on the control socket.
  wire::ControlRequest set;
  set.mutable_set_params()->set_stream_id("p");
  set.mutable_set_params()->set_result_form(wire::MESH);
  const wire::ControlReply r = h.control(set);
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ(r.result_form(), wire::MESH);
  h.send(mesh, spec_for("p", 3), 1);
  const client::ReceivedResult after = h.receive_decoded("p");
  EXPECT_EQ(after.header.form(), wire::MESH);
  EXPECT_EQ(after.mesh.positions, p.mesh.positions);
}

TEST(DaemonStream, ControlListsStreamsAndCountsWithPercentiles) {
  daemon::DaemonConfig c = test_config();
  c.streams["configured"] = c.defaults;
  DaemonHarness h(c);
  h.send(noisy_sphere(), spec_for("seen"), 0);
  h.receive_decoded("seen");
  wire::ControlRequest list;
  list.mutable_list_streams();
  const wire::ControlReply l = h.control(list);
  ASSERT_TRUE(l.ok());
  std::vector<std::string> ids(l.streams().begin(), l.streams().end());
  EXPECT_NE(std::find(ids.begin(), ids.end(), "configured"), ids.end());
  EXPECT_NE(std::find(ids.begin(), ids.end(), "seen"), ids.end());
  const wire::StreamCounters k = h.counters("seen");
  bool has_total = false;
  for (const wire::StagePercentiles& s : k.stages()) {
    if (s.name() != "receive_to_publish") continue;
    has_total = true;
    EXPECT_EQ(s.count(), 1u);
    EXPECT_GT(s.p50_ms(), 0.0);
    EXPECT_LE(s.p50_ms(), s.p99_ms());
  }
  EXPECT_TRUE(has_total);
}

}  // namespace
}  // namespace fq::test
