// fqpub against an fqd that refuses its CURVE key: it says so and exits 1 within 5 s (it used to
// wait for ever, saying only "no fqd connected"), and with an allowed key it still delivers,
// writing whole lines where its output goes to a pipe or a log.
#include <gtest/gtest.h>

#include <chrono>

#include "tests/daemon/fqd_process.h"
#include "tests/daemon/test_keys.h"

namespace fq::test {
namespace {

TEST(FqpubCurve, ARefusedKeyExitsOneWithinFiveSecondsSayingWhy) {
  const TestKeys keys;
  const std::string security = "[security]\ncurve_key_file = \"" + keys.server_key +
                               "\"\nclient_keys_file = \"" + keys.client_pub + "\"\n";
  FqdProcess fqd({"--config", write_temp_file("fqpub_refused.toml", ops_config(security))});
  ASSERT_FALSE(fqd.endpoint("ingest").empty());
  const std::string mesh = std::string(FQ_SOURCE_DIR) + "/data/fandisk.ply";
  const auto start = std::chrono::steady_clock::now();
  const ToolRun refused =
      run_tool(FQPUB_PATH, {mesh, "--endpoint", fqd.endpoint("ingest"), "--stream", "cam0", "--count", "3",
                            "--server-key", keys.server_pub, "--key-file", keys.stranger_key, "--quiet"});
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(refused.status, 1) << refused.output;
  EXPECT_LT(seconds, 5.0);
  EXPECT_NE(refused.output.find("refused our CURVE key"), std::string::npos) << refused.output;
  EXPECT_NE(refused.output.find("client_keys_file"), std::string::npos) << refused.output;
  // Without --quiet, into a pipe (as into a log file): whole lines, no progress redrawn with \r.
  const ToolRun allowed =
      run_tool(FQPUB_PATH, {mesh, "--endpoint", fqd.endpoint("ingest"), "--stream", "cam0", "--count", "2",
                            "--server-key", keys.server_pub, "--key-file", keys.client_key});
  EXPECT_EQ(allowed.status, 0) << allowed.output;
  EXPECT_EQ(allowed.output.find("refused"), std::string::npos) << allowed.output;
  EXPECT_EQ(allowed.output.find('\r'), std::string::npos) << allowed.output;
  EXPECT_NE(allowed.output.find("fqpub: stream 'cam0': 2 frames"), std::string::npos) << allowed.output;
}

}  // namespace
}  // namespace fq::test
