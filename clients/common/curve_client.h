// The client side of fqd's CURVE security, for every tool that connects to fqd:
//   --server-key KEY|FILE   fqd's public key (Z85, or a key file from fqkeys)
//   --key-file FILE         this client's key pair (fqkeys); its public key must be in
//                           fqd's security.client_keys_file
// Both or neither: without them the connection is plain (fqd without CURVE).
#pragma once

#include <string>
#include <zmq.hpp>

#include "common/status.h"

namespace CLI {
class App;
}

namespace fq::client {

struct CurveClientOptions {
  std::string server_key;  ///< Z85 or a key file path
  std::string key_file;
  bool enabled() const { return !server_key.empty() || !key_file.empty(); }
};

/// Adds --server-key and --key-file to a tool's command line.
void add_curve_options(CLI::App& app, CurveClientOptions& o);

/// Makes `socket` a CURVE client (before connect); ok and nothing done when not enabled.
Status apply_curve_client(zmq::socket_t& socket, const CurveClientOptions& o);

}  // namespace fq::client
