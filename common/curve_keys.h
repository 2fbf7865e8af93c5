// ZeroMQ CURVE keys: Z85 text (40 characters) as libzmq writes them, and key files in the
// format of libzmq's zmq_curve_keypair users (and of fqkeys):
//     public = "Z85..."
//     secret = "Z85..."      (absent in a public-key file)
// Shared by fqd (server side) and every client (fqpub, fqsub, fqctl).
#pragma once

#include <string>
#include <vector>

#include "common/status.h"

namespace fq {

struct CurveKeyPair {
  std::string public_key;  ///< Z85, 40 characters
  std::string secret_key;  ///< Z85, 40 characters; empty for a public-key file
};

/// True for a 40-character Z85 key.
bool valid_z85_key(const std::string& key);

/// A fresh key pair from libzmq (kUnavailable when libzmq was built without CURVE).
Status make_curve_key_pair(CurveKeyPair& out);

/// Reads a key file; `need_secret` refuses a file without a secret key.
Status read_curve_key_file(const std::string& path, bool need_secret, CurveKeyPair& out);

/// Writes `keys` (the secret only when non-empty) readable by the owner alone.
Status write_curve_key_file(const std::string& path, const CurveKeyPair& keys);

/// Every public key in a file: key files, or one Z85 key per line (# comments).
Status read_public_keys(const std::string& path, std::vector<std::string>& out);

}  // namespace fq
