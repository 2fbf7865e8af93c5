// The tools' CURVE options (fqpub, fqsub, fqctl), for apply_curve_client:
//   --server-key KEY|FILE   fqd's public key (Z85, or a key file from fqkeys)
//   --key-file FILE         this client's key pair (fqkeys)
#pragma once

#include <CLI/CLI.hpp>

#include "clients/common/curve_client.h"

namespace fq::client {

/// Adds --server-key and --key-file to a tool's command line.
void add_curve_options(CLI::App& app, CurveClientOptions& o);

}  // namespace fq::client
