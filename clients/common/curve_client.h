// The client side of fqd's CURVE security, for every program that connects to fqd: fqd's
// public key (Z85, or a key file from fqkeys) and this client's key pair file (fqkeys), whose
// public key must be in fqd's security.client_keys_file. Both or neither: without them the
// connection is plain (fqd without CURVE). The tools' --server-key and --key-file options
// are in curve_options.h.
#pragma once

#include <string>
#include <zmq.hpp>

#include "common/status.h"

namespace fq::client {

struct CurveClientOptions {
  std::string server_key;  ///< Z85 or a key file path
  std::string key_file;
  bool enabled() const { return !server_key.empty() || !key_file.empty(); }
};

/// Makes `socket` a CURVE client (before connect); ok and nothing done when not enabled.
Status apply_curve_client(zmq::socket_t& socket, const CurveClientOptions& o);

}  // namespace fq::client
