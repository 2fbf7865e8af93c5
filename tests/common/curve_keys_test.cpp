// CURVE key files: keys whose Z85 text holds '=' (about 38 % of them) read back from both file
// forms, as bare lines and as `public = "..."` entries.
#include <gtest/gtest.h>

#include <fstream>

#include "common/curve_keys.h"

namespace fq {
namespace {

TEST(CurveKeys, KeysHoldingAnEqualsSignReadBack) {
  std::vector<std::string> with_equals;
  for (int i = 0; i < 200 && with_equals.size() < 3; ++i) {
    CurveKeyPair p;
    ASSERT_TRUE(make_curve_key_pair(p).ok());
    if (p.public_key.find('=') != std::string::npos) with_equals.push_back(p.public_key);
  }
  ASSERT_EQ(with_equals.size(), 3u) << "no key with '=' in 200 tries";
  const std::string path = testing::TempDir() + "/fq_equals_keys.pub";
  {
    std::ofstream out(path);
    out << "# clients\n" << with_equals[0] << "\n" << with_equals[1] << "\npublic = \"" << with_equals[2] << "\"\n";
  }
  std::vector<std::string> keys;
  const Status s = read_public_keys(path, keys);
  ASSERT_TRUE(s.ok()) << s.message();
  EXPECT_EQ(keys, with_equals);
  CurveKeyPair file;
  ASSERT_TRUE(write_curve_key_file(path, {with_equals[0], ""}).ok());
  ASSERT_TRUE(read_curve_key_file(path, false, file).ok());
  EXPECT_EQ(file.public_key, with_equals[0]);
}

}  // namespace
}  // namespace fq
