// What a peer can make fqd show or keep about streams, over real sockets on 127.0.0.1: stream ids
// that act on a display are refused at every door; junk under a stream's id from a producer
// without CURVE is refused, not published as that stream's errors; set_params holds the config's
// ranges; and /metrics keeps series of their own only for the streams that are configured or
// recently active, every other stream summed into stream="other".
#include <gtest/gtest.h>

#include <chrono>
#include <functional>
#include <string>
#include <thread>

#include "daemon/stream/stream_admission.h"
#include "tests/daemon/daemon_harness.h"
#include "tests/daemon/http_metrics.h"
#include "tests/support/test_meshes.h"
#include "wire/header_codec.h"

namespace fq::test {
namespace {

client::FrameSpec spec_for(const std::string& stream) { return {.stream_id = stream, .overrides = {}}; }

template <class F>
bool within(std::chrono::seconds limit, F&& done) {
  const auto end = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < end) {
    if (done()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return done();
}

// Series with a stream label in a /metrics text.
size_t stream_series(const std::string& metrics) {
  size_t n = 0;
  for (size_t at = 0; (at = metrics.find("{stream=\"", at)) != std::string::npos; ++at) ++n;
  return n;
}

wire::ControlReply set_params(DaemonHarness& h, const std::string& id,
                              const std::function<void(wire::SetParams&)>& f) {
  wire::ControlRequest q;
  q.mutable_set_params()->set_stream_id(id);
  q.mutable_set_params()->set_create(true);
  f(*q.mutable_set_params());
  return h.control(q);
}

// ESC, CSI as one code point, a bidirectional override, a line separator, an isolate: each was
// taken as a stream id by the ingest and by set_params, and so echoed into logs, the viewer and
// /metrics as it was.
TEST(StreamExposure, IdsThatActOnADisplayAreRefusedAtTheIngestAndTheControlSocket) {
  DaemonHarness h;
  const Mesh mesh = noisy_sphere();
  // \u escapes end after four digits: "\u202E0" is U+202E then '0'.
  const std::string bad[] = {"cam\x1b[2J", "cam\u009B2J", "cam\u202E0", "cam\u2028", "cam\u2066"};
  uint64_t refused = 0;
  for (const std::string& id : bad) {
    SCOPED_TRACE(daemon::printable_id(id));
    std::vector<std::string> parts;
    ASSERT_TRUE(client::build_frame(mesh.view(), spec_for("cam"), 1, parts).ok());
    parts[0] = id;
    h.send_parts(parts);
    const client::ReceivedResult e = h.receive(daemon::printable_id(id));
    EXPECT_EQ(e.header.status(), wire::ERROR);
    EXPECT_NE(e.header.error().find("a bidirectional formatting character"), std::string::npos)
        << e.header.error();
    const wire::ControlReply r = set_params(h, id, [](wire::SetParams& q) { q.set_budget_ms(50); });
    EXPECT_FALSE(r.ok());
    EXPECT_NE(r.error().find("a bidirectional formatting character"), std::string::npos) << r.error();
    refused += 2;
    EXPECT_EQ(h.daemon()->registry().refusals().get(daemon::Refusal::kBadStreamId), refused);
    EXPECT_EQ(h.daemon()->registry().find(id), nullptr);
  }
  h.send(mesh, spec_for("cam"), 2);
  EXPECT_EQ(h.receive("cam").header.status(), wire::OK);
}

// A malformed message and an undecodable frame under a stream's id, from a producer without
// CURVE: before, each was published to the stream's subscribers as an error result and counted
// in the stream's errors (anyone who could connect could put errors on any stream).
TEST(StreamExposure, JunkUnderAStreamsIdFromAProducerWithoutCurveIsRefusedNotPublished) {
  DaemonHarness h;
  const Mesh mesh = noisy_sphere();
  h.send(mesh, spec_for("cam"), 1);
  ASSERT_EQ(h.receive("cam").header.status(), wire::OK);
  std::vector<std::string> good;
  ASSERT_TRUE(client::build_frame(mesh.view(), spec_for("cam"), 2, good).ok());
  std::vector<std::string> malformed = good;
  malformed[1] = "\xff\xff\xff";  // no frame header
  std::vector<std::string> undecodable = good;
  undecodable[2] = std::string(200, 'x');  // a header, but no Draco
  h.send_parts(malformed);
  h.send_parts(undecodable);
  const daemon::RefusalCounters& refusals = h.daemon()->registry().refusals();
  // Decoded before the next frame is sent, which would otherwise supersede it in the queue.
  ASSERT_TRUE(
      within(std::chrono::seconds(30), [&] { return refusals.get(daemon::Refusal::kUndecodable) == 1; }));
  h.send(mesh, spec_for("cam"), 3);
  // The next result on "cam" is the good frame's: nothing was published for the junk.
  const client::ReceivedResult next = h.receive("cam");
  EXPECT_EQ(next.header.status(), wire::OK);
  EXPECT_EQ(next.header.sequence(), 3u);
  EXPECT_EQ(refusals.get(daemon::Refusal::kMalformed), 1u);
  EXPECT_EQ(refusals.get(daemon::Refusal::kUndecodable), 1u);
  const wire::StreamCounters k = h.counters("cam");
  EXPECT_EQ(k.errors(), 0u);
  EXPECT_EQ(k.refused(), 1u) << "the undecodable frame, whose well-formed header had counted it in";
  EXPECT_EQ(k.frames_in(), k.frames_out() + k.errors() + k.superseded() + k.dropped_stale() + k.refused());
}

// Every setting beside the parameters, at and past each bound, through the config file and
// through set_params: before, set_params took budget_ms = 1e308 (the config: at most 1e6) and
// any budget above 0.
TEST(StreamExposure, SetParamsHoldsTheConfigsRangeForEverySetting) {
  struct Bound {
    const char* toml;  ///< the key in [defaults] or [defaults.output]
    bool output;
    double value;
    bool ok;
    std::function<void(wire::SetParams&)> set;
  };
  auto budget = [](double v) { return [v](wire::SetParams& q) { q.set_budget_ms(v); }; };
  auto bits = [](uint32_t v) { return [v](wire::SetParams& q) { q.set_position_bits(v); }; };
  auto enc = [](uint32_t v) { return [v](wire::SetParams& q) { q.set_encode_speed(v); }; };
  auto dec = [](uint32_t v) { return [v](wire::SetParams& q) { q.set_decode_speed(v); }; };
  auto chunks = [](uint32_t v) { return [v](wire::SetParams& q) { q.set_chunks(v); }; };
  const Bound bounds[] = {
      {"budget_ms", false, 0.001, true, budget(0.001)},
      {"budget_ms", false, 1e6, true, budget(1e6)},
      {"budget_ms", false, 0.0009, false, budget(0.0009)},
      {"budget_ms", false, 1.0001e6, false, budget(1.0001e6)},
      {"budget_ms", false, 1e308, false, budget(1e308)},
      {"position_bits", true, 8, true, bits(8)},
      {"position_bits", true, 30, true, bits(30)},
      {"position_bits", true, 7, false, bits(7)},
      {"position_bits", true, 31, false, bits(31)},
      {"encode_speed", true, 0, true, enc(0)},
      {"encode_speed", true, 10, true, enc(10)},
      {"encode_speed", true, 11, false, enc(11)},
      {"decode_speed", true, 0, true, dec(0)},
      {"decode_speed", true, 10, true, dec(10)},
      {"decode_speed", true, 11, false, dec(11)},
      {"chunks", true, 1, true, chunks(1)},
      {"chunks", true, 256, true, chunks(256)},
      {"chunks", true, 257, false, chunks(257)},
  };
  DaemonHarness h;
  for (const Bound& b : bounds) {
    char value[64];
    std::snprintf(value, sizeof value, b.toml == std::string("budget_ms") ? "%.17g" : "%.0f", b.value);
    SCOPED_TRACE(std::string(b.toml) + " = " + value);
    daemon::DaemonConfig c;
    const std::string text =
        std::string(b.output ? "[defaults.output]\n" : "[defaults]\n") + b.toml + " = " + value + "\n";
    EXPECT_EQ(daemon::parse_config(text, "t.toml", c).ok(), b.ok) << "the config file";
    const wire::ControlReply r = set_params(h, "cam", b.set);
    EXPECT_EQ(r.ok(), b.ok) << "set_params: " << r.error();
    if (!b.ok) {
      EXPECT_NE(r.error().find(b.toml), std::string::npos) << r.error();
    }
  }
}

// Stream ids that come and go: before, each kept ~40 series of its own for as long as it was
// registered (the whole of stream_idle_s, and for good with stream_idle_s = 0), so every id ever
// seen became series in the monitoring system. Now only the configured stream and the ones with
// a frame within metric_series_idle_s have their own; the rest count in stream="other", and the
// sums over streams never go down.
TEST(StreamExposure, MetricsKeepOwnSeriesForConfiguredAndRecentStreamsOnly) {
  daemon::DaemonConfig c = test_config();
  c.caps.max_streams = 256;
  c.caps.stream_idle_s = 0;  // never forgotten: the registry holds every id
  c.caps.metric_series_idle_s = 3;
  c.caps.max_subscriber_results = 64;
  c.defaults.params.cluster = false;
  c.streams["pinned"] = c.defaults;
  c.streams["__probe"] = c.defaults;  // the harness's: its frames are not the churn's
  c.http.listen = "127.0.0.1:0";
  DaemonHarness h(c);
  const std::string base = h.daemon()->endpoints().http;
  ASSERT_FALSE(base.empty());
  const Mesh mesh = noisy_sphere(7, 2);
  constexpr int kIds = 40;
  for (int k = 0; k < kIds; ++k) h.send(mesh, spec_for("churn-" + std::to_string(k)), 0);
  for (int k = 0; k < kIds; ++k) ASSERT_EQ(h.receive("churn-" + std::to_string(k)).header.status(), wire::OK);
  const std::string during = http_get(base, "/metrics");
  EXPECT_EQ(metric_value(during, "fq_frames_out_total{stream=\"churn-39\"}"), 1) << "active: its own series";
  std::this_thread::sleep_for(std::chrono::milliseconds(3500));
  h.send(mesh, spec_for("pinned"), 1);
  ASSERT_EQ(h.receive("pinned").header.status(), wire::OK);
  std::string after;
  ASSERT_TRUE(within(std::chrono::seconds(30), [&] {
    after = http_get(base, "/metrics");
    return after.find("churn-") == std::string::npos;
  })) << "ids without a frame for metric_series_idle_s kept their series";
  EXPECT_EQ(metric_value(after, "fq_frames_out_total{stream=\"other\"}"), kIds) << after.substr(0, 2000);
  EXPECT_EQ(metric_value(after, "fq_frames_in_total{stream=\"other\"}"), kIds);
  EXPECT_EQ(metric_value(after, "fq_stage_latency_seconds_count{stream=\"other\",stage=\"engine\"}"), kIds);
  EXPECT_EQ(metric_value(after, "fq_frames_out_total{stream=\"pinned\"}"), 1) << "configured: its own series";
  EXPECT_EQ(metric_value(after, "fq_streams"), kIds + 2) << "still registered (with the harness's probe)";
  // An id that comes back starts its own series from zero; "other" keeps what it had.
  h.send(mesh, spec_for("churn-0"), 1);
  ASSERT_EQ(h.receive("churn-0").header.status(), wire::OK);
  const std::string back = http_get(base, "/metrics");
  EXPECT_EQ(metric_value(back, "fq_frames_out_total{stream=\"churn-0\"}"), 1);
  EXPECT_EQ(metric_value(back, "fq_frames_out_total{stream=\"other\"}"), kIds);
  std::printf("/metrics: %zu per-stream series with %d ids active, %zu once they were idle\n",
              stream_series(during), kIds, stream_series(after));
}

}  // namespace
}  // namespace fq::test
