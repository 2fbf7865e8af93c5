#include "clients/common/curve_options.h"

namespace fq::client {

void add_curve_options(CLI::App& app, CurveClientOptions& o) {
  app.add_option("--server-key", o.server_key, "fqd's CURVE public key: Z85 text or a key file (fqkeys)")
      ->group("Security");
  app.add_option("--key-file", o.key_file, "this client's CURVE key pair file (fqkeys)")->group("Security");
}

}  // namespace fq::client
