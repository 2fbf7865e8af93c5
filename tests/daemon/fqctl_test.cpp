// fqctl against a real fqd (child process, ephemeral 127.0.0.1 ports) fed by fqpub:
// streams, params, set (valid, invalid, unknown key, unknown stream), counters and watch as 80-column tables,
// --json on every subcommand, and a clear error with exit status 1, not a hang, when no fqd
// answers.
#include <gtest/gtest.h>

#include <chrono>
#include <sstream>
#include <thread>
#include <utility>
#include <zmq.hpp>

#include "tests/daemon/fqd_process.h"

namespace fq::test {
namespace {

ToolRun fqctl(const std::string& control, std::vector<std::string> args) {
  args.insert(args.begin(), {"--control", control});
  return run_tool(FQCTL_PATH, args);
}

void expect_fits_80_columns(const std::string& output) {
  std::istringstream lines(output);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("\033[H\033[2J", 0) == 0) line.erase(0, 7);  // a terminal's redraw (none when piped)
    EXPECT_LE(line.size(), 80u) << line;
  }
}

// Counters once every frame fqpub sent has been accounted for (fqd idle for that stream).
nlohmann::json settled_counters(const std::string& control, const std::string& stream, uint64_t sent) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  nlohmann::json c;
  while (std::chrono::steady_clock::now() < deadline) {
    const ToolRun r = fqctl(control, {"counters", stream, "--json"});
    if (r.status != 0) return {};
    c = nlohmann::json::parse(r.output).at("streams").at(0);
    const uint64_t done = c.at("frames_out").get<uint64_t>() + c.at("errors").get<uint64_t>() +
                          c.at("superseded").get<uint64_t>() + c.at("dropped_stale").get<uint64_t>();
    if (c.at("frames_in") == sent && done == sent) return c;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));  // polling fqd, not ordering
  }
  ADD_FAILURE() << "frames not settled: " << c.dump();
  return c;
}

TEST(Fqctl, InspectsAndSteersARunningFqd) {
  FqdProcess fqd({"--config", write_temp_file("fqctl_test.toml", ops_config())});
  const std::string control = fqd.endpoint("control");
  ASSERT_FALSE(control.empty()) << "fqd did not start";
  ASSERT_EQ(publish_fandisk(fqd.endpoint("ingest"), "cam0", 8).status, 0);

  const ToolRun streams = fqctl(control, {"streams"});
  EXPECT_EQ(streams.status, 0) << streams.output;
  EXPECT_EQ(streams.output, "cam0\n");

  const ToolRun set =
      fqctl(control, {"set", "cam0", "sigma_s=3.5", "mode=BF", "compute=filter", "result_form=mesh"});
  EXPECT_EQ(set.status, 0) << set.output;
  const ToolRun params = fqctl(control, {"params", "cam0"});
  EXPECT_EQ(params.status, 0) << params.output;
  EXPECT_NE(params.output.find("sigma_s = 3.5\n"), std::string::npos) << params.output;
  EXPECT_NE(params.output.find("mode = bf\n"), std::string::npos) << params.output;
  EXPECT_NE(params.output.find("compute = filter\n"), std::string::npos) << params.output;
  EXPECT_NE(params.output.find("result_form = mesh\n"), std::string::npos) << params.output;
  // POSITIONS is enum value 0 on the wire, yet a real choice (unlike COMPUTE_DEFAULT).
  const ToolRun back = fqctl(control, {"set", "cam0", "result_form=positions"});
  EXPECT_EQ(back.status, 0) << back.output;
  EXPECT_NE(back.output.find("result_form = positions\n"), std::string::npos) << back.output;
  const ToolRun no_default = fqctl(control, {"set", "cam0", "compute=compute_default"});
  EXPECT_EQ(no_default.status, 2);
  EXPECT_NE(no_default.output.find("compute must be one of filter, cluster, filter_and_cluster"),
            std::string::npos)
      << no_default.output;

  // fqd refuses an invalid value (nothing changes); fqctl refuses an unknown key itself.
  const ToolRun invalid = fqctl(control, {"set", "cam0", "sigma_s=-1"});
  EXPECT_EQ(invalid.status, 1);
  EXPECT_NE(invalid.output.find("sigma_s"), std::string::npos) << invalid.output;
  EXPECT_NE(fqctl(control, {"params", "cam0"}).output.find("sigma_s = 3.5\n"), std::string::npos);
  const ToolRun unknown = fqctl(control, {"set", "cam0", "sigma_z=1"});
  EXPECT_EQ(unknown.status, 2);
  EXPECT_NE(unknown.output.find("unknown parameter 'sigma_z'"), std::string::npos) << unknown.output;
  EXPECT_EQ(fqctl(control, {"params", "nosuch"}).status, 1);

  const nlohmann::json c = settled_counters(control, "cam0", 8);
  EXPECT_EQ(c.at("stream"), "cam0");
  EXPECT_GT(c.at("frames_out").get<uint64_t>(), 0u);
  EXPECT_EQ(c.at("errors"), 0);
  EXPECT_EQ(c.at("stages").at("receive_to_publish").at("count"), c.at("frames_out"));

  const ToolRun table = fqctl(control, {"counters"});
  EXPECT_EQ(table.status, 0);
  EXPECT_NE(table.output.find("cam0"), std::string::npos) << table.output;
  const ToolRun watch = fqctl(control, {"watch", "--count", "2", "--interval", "0.1"});
  EXPECT_EQ(watch.status, 0) << watch.output;
  size_t headers = 0;
  for (size_t at = 0; (at = watch.output.find("superseded", at)) != std::string::npos; ++at) ++headers;
  EXPECT_EQ(headers, 2u) << watch.output;
  for (const std::string& output : {table.output, watch.output}) expect_fits_80_columns(output);
  EXPECT_EQ(fqd.stop(), 0);
}

// The parameters as configs spell them (qf+, auto), and the stream's budget and output
// encoding changed at run time like its parameters.
TEST(Fqctl, SetsModeAndBudgetInTheConfigsSpelling) {
  FqdProcess fqd({"--config", write_temp_file("fqctl_spelling_test.toml", ops_config())});
  const std::string control = fqd.endpoint("control");
  ASSERT_FALSE(control.empty()) << "fqd did not start";
  const ToolRun set = fqctl(control, {"set", "--create", "cam0", "mode=qf+", "budget_ms=250"});
  ASSERT_EQ(set.status, 0) << set.output;
  const ToolRun params = fqctl(control, {"params", "cam0"});
  ASSERT_EQ(params.status, 0) << params.output;
  for (const char* line : {"mode = qf+\n", "budget_ms = 250\n", "cluster_geometry = auto\n",
                           "cluster_method = quadric\n", "known_noise = 0\n", "temporal = 0\n"})
    EXPECT_NE(params.output.find(line), std::string::npos) << line << " in\n" << params.output;
  for (const char* wire_name : {"qf_plus", "geometry_auto", "QF_PLUS"})
    EXPECT_EQ(params.output.find(wire_name), std::string::npos) << params.output;

  const ToolRun output = fqctl(control, {"set", "cam0", "position_bits=12", "chunks=4", "encode_speed=5",
                                         "decode_speed=6", "cluster_geometry=filtered", "strength=0.5"});
  ASSERT_EQ(output.status, 0) << output.output;
  for (const char* line : {"position_bits = 12\n", "chunks = 4\n", "encode_speed = 5\n", "decode_speed = 6\n",
                           "cluster_geometry = filtered\n", "strength = 0.5\n", "mode = qf+\n"})
    EXPECT_NE(output.output.find(line), std::string::npos) << line << " in\n" << output.output;
  for (const std::vector<std::string>& bad : std::vector<std::vector<std::string>>{
           {"budget_ms=0"}, {"position_bits=40"}, {"chunks=300"}, {"encode_speed=11"}}) {
    const ToolRun r = fqctl(control, {"set", "cam0", bad[0]});
    EXPECT_EQ(r.status, 1) << bad[0] << ": " << r.output;
  }
  const ToolRun wrong = fqctl(control, {"set", "cam0", "mode=qf_plus"});
  EXPECT_EQ(wrong.status, 2);
  EXPECT_NE(wrong.output.find("mode must be one of qf+, qf, bf"), std::string::npos) << wrong.output;
  EXPECT_NE(fqctl(control, {"params", "cam0"}).output.find("budget_ms = 250\n"), std::string::npos);
  EXPECT_EQ(fqd.stop(), 0);
}

// A typo must not make a stream no producer feeds: set on a stream fqd does not know fails,
// naming the nearest known one, unless --create; a misspelled key names the nearest keys.
TEST(Fqctl, SetRefusesAnUnknownStreamUnlessCreateAndSuggestsNearNames) {
  FqdProcess fqd({"--config",
                  write_temp_file("fqctl_create_test.toml", ops_config("[streams.cam0]\nbudget_ms = 50\n"))});
  const std::string control = fqd.endpoint("control");
  ASSERT_FALSE(control.empty()) << "fqd did not start";

  const ToolRun typo = fqctl(control, {"set", "cma0", "budget_ms=10"});
  EXPECT_EQ(typo.status, 1) << typo.output;
  EXPECT_NE(typo.output.find("unknown stream 'cma0' (did you mean 'cam0'?)"), std::string::npos)
      << typo.output;
  EXPECT_NE(typo.output.find("--create"), std::string::npos) << typo.output;
  const ToolRun far = fqctl(control, {"set", "nosuch", "budget_ms=10"});
  EXPECT_EQ(far.status, 1) << far.output;
  EXPECT_NE(far.output.find("unknown stream 'nosuch'"), std::string::npos) << far.output;
  EXPECT_EQ(far.output.find("did you mean"), std::string::npos) << far.output;
  EXPECT_EQ(fqctl(control, {"streams"}).output, "cam0\n") << "a refused set made a stream";

  const ToolRun made = fqctl(control, {"set", "--create", "nosuch", "budget_ms=10"});
  EXPECT_EQ(made.status, 0) << made.output;
  EXPECT_NE(made.output.find("budget_ms = 10\n"), std::string::npos) << made.output;
  EXPECT_EQ(fqctl(control, {"streams"}).output, "cam0\nnosuch\n");
  const ToolRun known = fqctl(control, {"set", "cam0", "budget_ms=20"});
  EXPECT_EQ(known.status, 0) << known.output;
  EXPECT_NE(known.output.find("budget_ms = 20\n"), std::string::npos) << known.output;

  const ToolRun key = fqctl(control, {"set", "cam0", "budget_sm=20"});
  EXPECT_EQ(key.status, 2) << key.output;
  EXPECT_NE(key.output.find("unknown parameter 'budget_sm' (did you mean 'budget_ms'?)"), std::string::npos)
      << key.output;
  EXPECT_EQ(fqctl(control, {"set", "cam0", "create=true"}).status, 2) << "create is a flag, not a setting";
  EXPECT_EQ(fqd.stop(), 0);
}

TEST(Fqctl, JsonFromEverySubcommandAndTablesWithin80Columns) {
  FqdProcess fqd({"--config", write_temp_file("fqctl_json_test.toml", ops_config())});
  const std::string control = fqd.endpoint("control");
  ASSERT_FALSE(control.empty()) << "fqd did not start";
  const std::string long_id = "north_gate_camera_0042";
  ASSERT_EQ(publish_fandisk(fqd.endpoint("ingest"), long_id, 4).status, 0);
  settled_counters(control, long_id, 4);

  const auto json_of = [&](std::vector<std::string> args) {
    const ToolRun r = fqctl(control, std::move(args));
    EXPECT_EQ(r.status, 0) << r.output;
    return nlohmann::json::parse(r.output, nullptr, false);
  };
  EXPECT_EQ(json_of({"streams", "--json"}).at("streams"), nlohmann::json::array({long_id}));
  const nlohmann::json set = json_of({"set", long_id, "sigma_s=2.5", "mode=qf", "--json"});
  EXPECT_EQ(set.at("stream"), long_id);
  EXPECT_EQ(set.at("params").at("sigma_s"), 2.5);  // numbers as numbers
  EXPECT_EQ(set.at("params").at("mode"), "qf");    // names as strings
  EXPECT_EQ(json_of({"params", long_id, "--json"}).at("params"), set.at("params"));
  EXPECT_EQ(json_of({"counters", long_id, "--json"}).at("streams").at(0).at("frames_in"), 4);
  const ToolRun watch = fqctl(control, {"watch", "--count", "2", "--interval", "0.1", "--json"});
  ASSERT_EQ(watch.status, 0) << watch.output;
  std::istringstream lines(watch.output);
  std::string first, second;
  std::getline(lines, first);
  std::getline(lines, second);
  EXPECT_TRUE(nlohmann::json::parse(first).at("streams").at(0).at("fps").is_null());  // no rate yet
  EXPECT_EQ(nlohmann::json::parse(second).at("streams").at(0).at("fps"), 0.0);        // idle since
  // A long stream id is cut in the tables, which stay within 80 columns.
  const ToolRun table = fqctl(control, {"counters"});
  expect_fits_80_columns(table.output);
  EXPECT_NE(table.output.find("north_gate_~"), std::string::npos) << table.output;
  EXPECT_EQ(fqd.stop(), 0);
}

TEST(Fqctl, SaysSoAndFailsWhenNoFqdAnswers) {
  // A port that was free a moment ago: nothing answers there.
  zmq::context_t ctx(1);
  zmq::socket_t probe(ctx, zmq::socket_type::rep);
  probe.bind("tcp://127.0.0.1:*");
  const std::string endpoint = probe.get(zmq::sockopt::last_endpoint);
  probe.close();
  for (const char* command : {"streams", "counters", "watch"}) {
    const ToolRun r = run_tool(FQCTL_PATH, {"--control", endpoint, "--timeout-ms", "300", command}, 60);
    EXPECT_EQ(r.status, 1) << command << ": " << r.output;
    EXPECT_NE(r.output.find("no reply from fqd at " + endpoint), std::string::npos) << r.output;
  }
  EXPECT_EQ(run_tool(FQCTL_PATH, {"--control", "nonsense", "streams"}).status, 1);
}

}  // namespace
}  // namespace fq::test
