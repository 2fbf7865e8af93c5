#include "clients/common/curve_client.h"

#include "common/curve_keys.h"

namespace fq::client {

Status apply_curve_client(zmq::socket_t& socket, const CurveClientOptions& o) {
  if (!o.enabled()) return {};
  if (o.server_key.empty() || o.key_file.empty())
    return invalid_argument("CURVE needs both --server-key and --key-file");
  std::string server = o.server_key;
  if (!valid_z85_key(server)) {
    CurveKeyPair k;
    if (Status s = read_curve_key_file(o.server_key, false, k); !s.ok())
      return invalid_argument("--server-key is neither a Z85 key nor a readable key file: " + s.message());
    server = k.public_key;
  }
  CurveKeyPair mine;
  if (Status s = read_curve_key_file(o.key_file, true, mine); !s.ok()) return s;
  socket.set(zmq::sockopt::curve_serverkey, server);
  socket.set(zmq::sockopt::curve_publickey, mine.public_key);
  socket.set(zmq::sockopt::curve_secretkey, mine.secret_key);
  return {};
}

}  // namespace fq::client
