// CURVE key files: keys whose Z85 text holds '=' (about 38 % of them) read back from both file
// forms, as bare lines and as `public = "..."` entries.
#include "common/curve_keys.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>

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
    out << "# clients\n"
        << with_equals[0] << "\n"
        << with_equals[1] << "\npublic = \"" << with_equals[2] << "\"\n";
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

mode_t mode_of(const std::string& path) {
  struct stat st {};
  EXPECT_EQ(::stat(path.c_str(), &st), 0);
  return st.st_mode & 0777;
}

TEST(CurveKeys, SecretKeyFilesAreOwnerOnlyEvenOverAWiderFile) {
  CurveKeyPair pair;
  ASSERT_TRUE(make_curve_key_pair(pair).ok());
  const std::string dir = ::testing::TempDir();
  const std::string secret = dir + "/fq_curve_secret.key", pub = dir + "/fq_curve_public.pub";
  // A file already there, readable by everyone: writing a secret into it narrows it first.
  { std::ofstream(secret) << "old"; }
  ASSERT_EQ(::chmod(secret.c_str(), 0666), 0);
  ASSERT_TRUE(write_curve_key_file(secret, pair).ok());
  EXPECT_EQ(mode_of(secret), mode_t(0600));
  CurveKeyPair back;
  ASSERT_TRUE(read_curve_key_file(secret, true, back).ok());
  EXPECT_EQ(back.secret_key, pair.secret_key);
  std::filesystem::remove(pub);
  ASSERT_TRUE(write_curve_key_file(pub, {pair.public_key, ""}).ok());
  EXPECT_EQ(mode_of(pub) & 0600, mode_t(0600));
  // A folder that does not exist is an error with the path, not a silent success.
  const Status s = write_curve_key_file(dir + "/no/such/folder/x.key", pair);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.message().find("no/such/folder"), std::string::npos);
  std::filesystem::remove(secret);
  std::filesystem::remove(pub);
}

}  // namespace
}  // namespace fq
