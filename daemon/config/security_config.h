// [security] of fqd's configuration: which CURVE keys the three sockets use. Apart from
// curve_auth.h (which reads the files and runs the ZAP handler) so that the configuration
// does not depend on ZeroMQ's authentication.
#pragma once

#include <string>

namespace fq::daemon {

struct SecurityConfig {
  std::string curve_key_file;    ///< fqd's key pair (public + secret); empty: CURVE off
  std::string client_keys_file;  ///< client public keys allowed in; required with CURVE
  /// Client public keys allowed on the control socket instead of client_keys_file's; empty:
  /// client_keys_file's keys reach the control socket too.
  std::string control_keys_file;
  bool enabled() const { return !curve_key_file.empty(); }

  bool operator==(const SecurityConfig&) const = default;
};

}  // namespace fq::daemon
