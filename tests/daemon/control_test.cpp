// The control request handler without sockets: malformed and empty requests get ok = false;
// set_params changes only streams fqd knows unless asked to create one.
#include <gtest/gtest.h>

#include "daemon/control/control_server.h"
#include "wire/header_codec.h"

namespace fq::daemon {
namespace {

TEST(ControlHandler, GarbageAndEmptyRequestsGetErrorReplies) {
  DaemonConfig c;
  StreamRegistry r(c);
  wire::ControlReply reply;
  ASSERT_TRUE(wire::parse_control_reply(handle_control_bytes("\xff\x01garbage", r, c.caps), reply).ok());
  EXPECT_FALSE(reply.ok());
  EXPECT_FALSE(reply.error().empty());
  ASSERT_TRUE(wire::parse_control_reply(handle_control_bytes("", r, c.caps), reply).ok());
  EXPECT_FALSE(reply.ok());
}

TEST(ControlHandler, SetParamsValidatesAndGetParamsReadsBack) {
  DaemonConfig c;
  StreamRegistry r(c);
  wire::ControlRequest set;
  set.mutable_set_params()->set_stream_id("s");
  set.mutable_set_params()->set_create(true);
  set.mutable_set_params()->mutable_params()->set_sigma_r(-1.0f);
  EXPECT_FALSE(handle_control(set, r, c.caps).ok());
  set.mutable_set_params()->mutable_params()->set_sigma_r(0.5f);
  set.mutable_set_params()->set_compute(wire::CLUSTER);
  ASSERT_TRUE(handle_control(set, r, c.caps).ok());
  StreamSettings s;
  ASSERT_TRUE(r.find("s", s));
  EXPECT_FLOAT_EQ(s.params.filtering.sigma_r, 0.5f);
  EXPECT_FALSE(s.params.filter);
  EXPECT_TRUE(s.params.cluster);
  wire::ControlRequest get;
  get.mutable_get_params()->set_stream_id("s");
  const wire::ControlReply g = handle_control(get, r, c.caps);
  ASSERT_TRUE(g.ok());
  EXPECT_FLOAT_EQ(g.params().sigma_r(), 0.5f);
  EXPECT_EQ(g.compute(), wire::CLUSTER);
  EXPECT_EQ(g.result_form(), wire::POSITIONS);
  EXPECT_EQ(g.version(), wire::kWireVersion);
  set.mutable_set_params()->set_result_form(wire::MESH);
  EXPECT_EQ(handle_control(set, r, c.caps).result_form(), wire::MESH);
  ASSERT_TRUE(r.find("s", s));
  EXPECT_EQ(s.output.form, ResultForm::kMesh);
}

TEST(ControlHandler, AnotherVersionIsRefusedNamingBothVersions) {
  DaemonConfig c;
  StreamRegistry r(c);
  wire::ControlRequest q;
  q.mutable_list_streams();
  q.set_version(1);
  wire::ControlReply reply;
  ASSERT_TRUE(wire::parse_control_reply(handle_control_bytes(q.SerializeAsString(), r, c.caps), reply).ok());
  EXPECT_FALSE(reply.ok());
  EXPECT_NE(reply.error().find("wire version 1 not supported (this build speaks version 2)"),
            std::string::npos)
      << reply.error();
  q.set_version(wire::kWireVersion);
  ASSERT_TRUE(wire::parse_control_reply(handle_control_bytes(q.SerializeAsString(), r, c.caps), reply).ok());
  EXPECT_TRUE(reply.ok()) << reply.error();
}

TEST(ControlHandler, SetParamsTakesOnlyStreamIdsTheIngestWouldAdmit) {
  DaemonConfig c;
  c.caps.allowed_streams = {"cam*"};
  StreamRegistry r(c);
  auto set = [&](const std::string& id) {
    wire::ControlRequest q;
    q.mutable_set_params()->set_stream_id(id);
    q.mutable_set_params()->set_create(true);
    q.mutable_set_params()->mutable_params()->set_sigma_r(0.5f);
    return handle_control(q, r, c.caps);
  };
  // A newline would forge a log line; a 16 MiB id would sit in every /metrics scrape.
  const wire::ControlReply forged = set("cam\n[critical] fqd: forged");
  EXPECT_FALSE(forged.ok());
  EXPECT_NE(forged.error().find("cam\\x0a[critical]"), std::string::npos) << forged.error();
  EXPECT_FALSE(set("cam" + std::string(16 << 20, 'x')).ok());
  EXPECT_FALSE(set("studio").ok());  // not in caps.allowed_streams
  EXPECT_TRUE(set("cam0").ok());
  EXPECT_EQ(r.list(), std::vector<std::string>{"cam0"});
  EXPECT_EQ(r.refusals().get(Refusal::kBadStreamId), 2u);
  EXPECT_EQ(r.refusals().get(Refusal::kNotAllowed), 1u);
  wire::ControlRequest get;
  get.mutable_get_params()->set_stream_id("no\nsuch");
  EXPECT_NE(handle_control(get, r, c.caps).error().find("no\\x0asuch"), std::string::npos);
}

// A typo in a stream id must not make a stream no producer feeds: without `create` only a
// stream fqd knows (configured or seen) is changed, and the refusal names the nearest one.
TEST(ControlHandler, SetParamsForAnUnknownStreamNeedsCreate) {
  DaemonConfig c;
  c.streams["cam0"] = c.defaults;
  StreamRegistry r(c);
  auto set = [&](const std::string& id, bool create) {
    wire::ControlRequest q;
    q.mutable_set_params()->set_stream_id(id);
    if (create) q.mutable_set_params()->set_create(true);
    q.mutable_set_params()->set_budget_ms(10.0);
    return handle_control(q, r, c.caps);
  };
  const wire::ControlReply typo = set("cam1", false);
  EXPECT_FALSE(typo.ok());
  EXPECT_NE(typo.error().find("unknown stream 'cam1' (did you mean 'cam0'?)"), std::string::npos)
      << typo.error();
  EXPECT_NE(typo.error().find("create"), std::string::npos) << typo.error();
  const wire::ControlReply far = set("nosuch", false);
  EXPECT_FALSE(far.ok());
  EXPECT_EQ(far.error().find("did you mean"), std::string::npos) << far.error();
  EXPECT_EQ(r.list(), std::vector<std::string>{"cam0"}) << "a refused set made a stream";

  EXPECT_TRUE(set("cam0", false).ok()) << "a configured stream needs no create";
  const wire::ControlReply made = set("cam1", true);
  ASSERT_TRUE(made.ok()) << made.error();
  EXPECT_EQ(made.budget_ms(), 10.0);
  EXPECT_EQ(r.list(), (std::vector<std::string>{"cam0", "cam1"}));
  EXPECT_TRUE(set("cam1", false).ok()) << "once made, it is known";
}

}  // namespace
}  // namespace fq::daemon
