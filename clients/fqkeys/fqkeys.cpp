// fqkeys: makes a ZeroMQ CURVE key pair for fqd or one of its clients.
//   fqkeys NAME   ->  NAME.key (public + secret, owner-only) and NAME.pub (public only)
// Give fqd its .key (security.curve_key_file) and the clients' .pub files
// (security.client_keys_file); give each client its own .key and fqd's .pub (--server-key).
#include <CLI/CLI.hpp>
#include <cstdio>

#include "clients/common/tool_app.h"
#include "common/curve_keys.h"
#include "common/tool_main.h"

namespace {

int run(int argc, char** argv) {
  fq::client::ToolApp app{"fqkeys: make a CURVE key pair (NAME.key with the secret, NAME.pub without)",
                          "fqkeys"};
  std::string name;
  bool force = false;
  app.add_option("name", name, "path prefix of the two files")->required();
  app.add_flag("-f,--force", force, "overwrite existing files");
  CLI11_PARSE(app, argc, argv);
  const std::string key = name + ".key", pub = name + ".pub";
  if (!force)
    for (const std::string& p : {key, pub})
      if (std::FILE* f = std::fopen(p.c_str(), "r")) {
        std::fclose(f);
        std::fprintf(stderr, "fqkeys: %s exists (use --force to overwrite)\n", p.c_str());
        return 2;
      }
  fq::CurveKeyPair k;
  fq::Status s = fq::make_curve_key_pair(k);
  if (s.ok()) s = fq::write_curve_key_file(key, k);
  if (s.ok()) s = fq::write_curve_key_file(pub, {k.public_key, ""});
  if (!s.ok()) {
    std::fprintf(stderr, "fqkeys: %s\n", s.message().c_str());
    return 1;
  }
  std::printf("%s\n", k.public_key.c_str());
  std::fprintf(stderr, "fqkeys: wrote %s (keep it secret) and %s\n", key.c_str(), pub.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return fq::tool_main("fqkeys", run, argc, argv); }
