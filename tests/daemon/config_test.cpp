// Configuration parsing and validation: the shipped config, defaults, overrides, and a
// clear message naming the key for each kind of mistake.
#include "daemon/config/config.h"

#include <gtest/gtest.h>

#include "core/param_table.h"
#include "tests/support/param_values.h"

namespace fq::daemon {
namespace {

Status parse(const std::string& text, DaemonConfig& c) { return parse_config(text, "test.toml", c); }

// The error message for `text`, which must be rejected.
std::string error_of(const std::string& text) {
  DaemonConfig c;
  const Status s = parse(text, c);
  EXPECT_FALSE(s.ok()) << "accepted: " << text;
  return s.message();
}

TEST(DaemonConfig, ShippedDefaultConfigIsValid) {
  DaemonConfig c;
  const Status s = load_config(std::string(FQ_SOURCE_DIR) + "/configs/fqd.toml", c);
  ASSERT_TRUE(s.ok()) << s.message();
  EXPECT_EQ(c.engine.kind, EngineKind::kAuto);
  EXPECT_NE(c.endpoints.ingest.find("127.0.0.1"), std::string::npos);
  EXPECT_TRUE(c.defaults.params.filter);
  EXPECT_TRUE(c.defaults.params.cluster);
  ASSERT_EQ(c.streams.count("preview"), 1u);
  EXPECT_FLOAT_EQ(c.streams["preview"].params.filtering.sigma_s, 3.0f);
}

TEST(DaemonConfig, EmptyFileGivesBuiltInDefaults) {
  DaemonConfig c;
  ASSERT_TRUE(parse("", c).ok());
  EXPECT_EQ(c.decode_threads, 0);  // automatic
  c.resolve_auto_threads();
  EXPECT_GE(c.decode_threads, 2);
  EXPECT_GE(c.encode_threads, 2);
  EXPECT_EQ(c.defaults.output.position_bits, 16);
  EXPECT_EQ(c.defaults.output.chunks, 0u);
  EXPECT_EQ(c.defaults.output.form, ResultForm::kPositions);
  EXPECT_DOUBLE_EQ(c.defaults.budget_ms, 100.0);
}

TEST(DaemonConfig, StreamsInheritDefaultsAndOverrideSomeKeys) {
  DaemonConfig c;
  const Status s = parse(R"(
[defaults]
budget_ms = 40
compute = "filter"
[defaults.filter]
sigma_s = 3
sigma_r = 0.5
[streams.cam1.filter]
sigma_s = 1.5
[streams.cam1.output]
chunks = 4
position_bits = 12
result_form = "mesh"
[streams.cam2]
compute = "cluster"
[streams.cam2.cluster]
method = "euclidean"
theta = 0.5
target_clusters = 40
geometry = "input"
min_cluster_size = 8
track_ids = false
sticky_rings = 3
)",
                         c);
  ASSERT_TRUE(s.ok()) << s.message();
  const StreamSettings& a = c.settings_for("cam1");
  EXPECT_FLOAT_EQ(a.params.filtering.sigma_s, 1.5f);
  EXPECT_FLOAT_EQ(a.params.filtering.sigma_r, 0.5f);  // from [defaults]
  EXPECT_DOUBLE_EQ(a.budget_ms, 40.0);
  EXPECT_EQ(a.output.chunks, 4u);
  EXPECT_EQ(a.output.position_bits, 12);
  EXPECT_EQ(a.output.form, ResultForm::kMesh);
  EXPECT_EQ(c.settings_for("cam2").output.form, ResultForm::kPositions);
  EXPECT_FALSE(a.params.cluster);
  const StreamSettings& b = c.settings_for("cam2");
  EXPECT_FALSE(b.params.filter);
  EXPECT_TRUE(b.params.cluster);
  EXPECT_EQ(b.params.clustering.method, ClusterMethod::kEuclidean);
  EXPECT_EQ(b.params.clustering.target_clusters, 40u);
  EXPECT_EQ(b.params.clustering.geometry, ClusterGeometry::kInput);
  EXPECT_EQ(b.params.clustering.min_cluster_size, 8u);
  EXPECT_FALSE(b.params.clustering.track_ids);
  EXPECT_EQ(b.params.clustering.sticky_rings, 3u);
  EXPECT_TRUE(a.params.clustering.track_ids) << "ids are tracked unless a stream says otherwise";
  EXPECT_EQ(a.params.clustering.geometry, ClusterGeometry::kAuto);
  EXPECT_FLOAT_EQ(c.settings_for("unlisted").params.filtering.sigma_s, 3.0f);
}

// Every TOML row of the parameter table (the filter's, "qf+"'s noise, the temporal strength,
// the clustering's) set per stream, each to a value other than its default, arrives.
TEST(DaemonConfig, AStreamSetsEveryTableParameter) {
  std::string filter = "[streams.cam9.filter]\n", cluster = "[streams.cam9.cluster]\n";
  for (const ParamRow& row : param_table()) {
    if (!row.on(kToml)) continue;
    const std::string text = format_param(row, test::other_value(row));
    (row.group == ParamGroup::kCluster ? cluster : filter) +=
        std::string(row.toml_key()) + " = " + (row.kind == ParamKind::kEnum ? "\"" + text + "\"" : text) +
        "\n";
  }
  DaemonConfig c;
  const Status s = parse("[streams.cam9]\nbudget_ms = 250\n" + filter + cluster, c);
  ASSERT_TRUE(s.ok()) << s.message() << "\n" << filter << cluster;
  const StreamSettings& got = c.settings_for("cam9");
  EXPECT_EQ(got.budget_ms, 250.0);
  for (const ParamRow& row : param_table()) {
    if (!row.on(kToml)) continue;
    EXPECT_EQ(row.get(got.params), test::other_value(row)) << row.name;
    EXPECT_EQ(row.get(c.defaults.params), row.get(Params{})) << row.name << ": [defaults] untouched";
  }
  for (const char* key : {"known_noise", "strength", "temporal"})
    EXPECT_NE(filter.find(key), std::string::npos) << key << " has no TOML row";
}

TEST(DaemonConfig, UnknownKeysAreNamedWithTheirLine) {
  EXPECT_NE(error_of("bogus = 1").find("unknown key 'bogus'"), std::string::npos);
  const std::string m = error_of("[defaults.filter]\nsigma_s = 2\nsigmaa_r = 1\n");
  EXPECT_NE(m.find("unknown key 'defaults.filter.sigmaa_r'"), std::string::npos) << m;
  EXPECT_NE(m.find("test.toml:3"), std::string::npos) << m;
  EXPECT_NE(error_of("[streams.cam.output]\nbits = 3\n").find("streams.cam.output.bits"), std::string::npos);
  EXPECT_NE(error_of("[caps]\nmax_vertex = 3\n").find("caps.max_vertex"), std::string::npos);
}

TEST(DaemonConfig, WrongTypesAndRangesAreRejected) {
  EXPECT_NE(error_of("[threads]\ndecode = \"two\"\n").find("threads.decode must be an integer"),
            std::string::npos);
  EXPECT_NE(error_of("[threads]\nencode = -1\n").find("threads.encode must be in"), std::string::npos);
  EXPECT_NE(error_of("[defaults.filter]\nsigma_s = \"big\"\n").find("must be a number"), std::string::npos);
  EXPECT_NE(error_of("[defaults.output]\nchunks = 0\n").find("chunks"), std::string::npos);
  EXPECT_NE(error_of("[defaults.output]\nposition_bits = 40\n").find("position_bits"), std::string::npos);
  EXPECT_NE(error_of("[defaults]\nbudget_ms = -5\n").find("budget_ms"), std::string::npos);
  EXPECT_NE(error_of("engine = 3\n").find("engine must be a table"), std::string::npos);
  EXPECT_NE(error_of("[engine]\ngpus = [0, \"one\"]\n").find("engine.gpus"), std::string::npos);
  EXPECT_NE(error_of("log_level = \"loud\"\n").find("log_level"), std::string::npos);
  EXPECT_NE(error_of("[caps]\nmax_subscriber_results = 1\n").find("caps.max_subscriber_results"),
            std::string::npos);
  EXPECT_NE(error_of("[caps]\nengine_time_limit_s = -1\n").find("caps.engine_time_limit_s"),
            std::string::npos);
}

TEST(DaemonConfig, TimeLimitGraceAndSubscriberQueueAreRead) {
  DaemonConfig c;
  ASSERT_TRUE(parse("", c).ok());
  EXPECT_DOUBLE_EQ(c.caps.engine_time_limit_s, 10.0);
  EXPECT_DOUBLE_EQ(c.caps.stop_grace_s, 1.0);
  EXPECT_EQ(c.caps.max_subscriber_results, 16u);
  ASSERT_TRUE(
      parse("[caps]\nengine_time_limit_s = 0.5\nstop_grace_s = 3\nmax_subscriber_results = 4\n", c).ok());
  EXPECT_DOUBLE_EQ(c.caps.engine_time_limit_s, 0.5);
  EXPECT_DOUBLE_EQ(c.caps.stop_grace_s, 3.0);
  EXPECT_EQ(c.caps.max_subscriber_results, 4u);
}

TEST(DaemonConfig, BadNamesAndParametersAreRejected) {
  EXPECT_NE(error_of("[engine]\nkind = \"gpu\"\n").find("engine.kind"), std::string::npos);
  EXPECT_NE(error_of("[defaults]\ncompute = \"both\"\n").find("compute"), std::string::npos);
  EXPECT_NE(error_of("[defaults.filter]\nmethod = \"median\"\n").find("method"), std::string::npos);
  EXPECT_NE(error_of("[defaults.cluster]\ngeometry = \"mesh\"\n").find("geometry"), std::string::npos);
  EXPECT_NE(error_of("[defaults.cluster]\nsticky_rings = 100\n").find("sticky_rings"), std::string::npos);
  EXPECT_NE(error_of("[defaults.cluster]\ntarget_clusters = -1\n").find("target_clusters"),
            std::string::npos);
  EXPECT_NE(
      error_of("[defaults.output]\nresult_form = \"faces\"\n").find("result_form must be \"positions\" or"),
      std::string::npos);
  EXPECT_NE(error_of("[defaults.filter]\nsigma_s = 0\n").find("sigma_s must be > 0"), std::string::npos);
  const std::string m = error_of("[streams.cam.cluster]\ntheta = 1.5\n");
  EXPECT_NE(m.find("streams.cam"), std::string::npos) << m;
  EXPECT_NE(m.find("theta"), std::string::npos) << m;
  EXPECT_NE(error_of("[endpoints]\ningest = \"tcp://127.0.0.1:1\"\npublish = \"tcp://127.0.0.1:1\"\n")
                .find("differ"),
            std::string::npos);
  EXPECT_NE(error_of("[engine]\nkind = \"cuda\"\ngpus = []\n").find("gpus"), std::string::npos);
}

TEST(DaemonConfig, EphemeralPortsMayRepeat) {
  for (const char* port : {"*", "0"}) {
    DaemonConfig c;
    const std::string ep = std::string("\"tcp://127.0.0.1:") + port + "\"";
    const Status s =
        parse("[endpoints]\ningest = " + ep + "\npublish = " + ep + "\ncontrol = " + ep + "\n", c);
    EXPECT_TRUE(s.ok()) << s.message();
  }
}

TEST(DaemonConfig, RangeErrorsNameTheLine) {
  std::string m = error_of("[defaults.filter]\nsigma_s = 0\n");
  EXPECT_NE(m.find("test.toml:2: defaults.filter.sigma_s must be > 0"), std::string::npos) << m;
  m = error_of("[streams.cam]\nbudget_ms = 50\n[streams.cam.cluster]\ntheta = 1.5\n");
  EXPECT_NE(m.find("test.toml:4: streams.cam.cluster.theta must be"), std::string::npos) << m;
  m = error_of("[caps]\n\nmax_streams = 0\n");
  EXPECT_NE(m.find("test.toml:3: caps.max_streams must be in [1, "), std::string::npos) << m;
  m = error_of("[endpoints]\ningest = \"tcp://127.0.0.1:1\"\npublish = \"tcp://127.0.0.1:1\"\n");
  EXPECT_NE(m.find("test.toml:2: endpoints.ingest must differ"), std::string::npos) << m;
  m = error_of("streams = { cam = 3 }\n");
  EXPECT_NE(m.find("test.toml:1: streams.cam must be a table"), std::string::npos) << m;
}

TEST(DaemonConfig, KeysKeepTheirLinesForLaterMessages) {
  DaemonConfig c;
  ASSERT_TRUE(parse("log_level = \"info\"\n[http]\n\ntoken_file = \"/t\"\n[ingest]\nconnect = "
                    "[\"tcp://a:1\",\n \"tcp://b:2\"]\n",
                    c)
                  .ok());
  EXPECT_EQ(c.where("http.token_file"), "test.toml:4");
  EXPECT_EQ(c.where("ingest.connect[1]"), "test.toml:7");
  EXPECT_EQ(c.where("http.web_root"), "test.toml:2") << "a key the file does not set: its table";
  EXPECT_EQ(c.where("security.curve_key_file"), "test.toml") << "nor its table";
}

TEST(DaemonConfig, SyntaxErrorsNameTheLine) {
  const std::string m = error_of("[defaults]\nbudget_ms = \n");
  EXPECT_NE(m.find("test.toml:2"), std::string::npos) << m;
}

TEST(DaemonConfig, MissingFileIsAClearError) {
  DaemonConfig c;
  const Status s = load_config("/nonexistent/fqd.toml", c);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.message().find("/nonexistent/fqd.toml"), std::string::npos);
}

}  // namespace
}  // namespace fq::daemon

namespace fq::daemon {
namespace {

// The config's stream tables and [ingest] streams are doors for stream ids like the ingest:
// before, any TOML key became a stream, a bidirectional override or an escape sequence included.
TEST(DaemonConfig, StreamTablesAndIngestStreamsTakeOnlyIdsTheIngestAdmits) {
  for (const char* key : {"\"cam\\u202e0\"", "\"cam\\u001b[31m\"", "\"cam\\u009b\"", "\"cam\\u2028\""}) {
    const std::string m = error_of(std::string("[streams.") + key + "]\nbudget_ms = 50\n");
    EXPECT_NE(m.find("stream id holds a control character"), std::string::npos) << m;
  }
  const std::string m = error_of("[ingest]\nconnect = [\"tcp://127.0.0.1:1\"]\nstreams = [\"cam\\u2066\"]\n");
  EXPECT_NE(m.find("ingest.streams: stream id holds"), std::string::npos) << m;
  DaemonConfig c;
  EXPECT_TRUE(parse("[streams.\"Kamera-\\u00fc\"]\nbudget_ms = 50\n", c).ok());
}

// Each [streams.*] table is a stream fqd keeps for good; more than caps.max_streams of them
// took slots that no frame could then get.
TEST(DaemonConfig, StreamTablesPastMaxStreamsAreRefused) {
  std::string text = "[caps]\nmax_streams = 2\n";
  for (int i = 0; i < 3; ++i) text += "[streams.cam" + std::to_string(i) + "]\nbudget_ms = 50\n";
  const std::string m = error_of(text);
  EXPECT_NE(m.find("3 [streams.*] tables, over caps.max_streams = 2"), std::string::npos) << m;
  DaemonConfig c;
  EXPECT_TRUE(parse(text.substr(0, text.rfind("[streams.cam2]")), c).ok());
}

// A bad value is echoed as a bounded prefix with its size: a 1 MiB string made a 1 MiB message
// (and a log line of that size on a reload).
TEST(DaemonConfig, AHugeBadValueIsEchoedAsABoundedPrefix) {
  const std::string huge(1u << 20, 'x');
  for (const std::string& text :
       {"[defaults]\ncompute = \"" + huge + "\"\n", "[engine]\nkind = \"" + huge + "\"\n",
        "[defaults.output]\nresult_form = \"" + huge + "\"\n",
        "[defaults.filter]\nmethod = \"" + huge + "\"\n", huge + " = 1\n",
        "[streams." + huge + "]\nbudget_ms = 50\n"}) {
    const std::string m = error_of(text);
    EXPECT_LT(m.size(), 1024u) << m.substr(0, 200);
    EXPECT_NE(m.find("...(1048576 bytes)"), std::string::npos) << m.substr(0, 200);
  }
}

}  // namespace
}  // namespace fq::daemon
