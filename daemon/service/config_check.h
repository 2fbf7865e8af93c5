// What fqd reads or binds at start beyond the TOML text, checked before it starts: the syntax
// of every ZeroMQ endpoint (zmq_endpoint.h; nothing is bound) and every file the configuration
// names, opened and read as the start reads it (the CURVE key pair and client keys, the HTTP
// token, the TLS certificate and key), and the viewer's folder when the file names one.
// `fqd --check-config` and the start run the same check, so a configuration it accepts does not
// stop fqd at start for what it says (exit 2); only what no check can know beforehand (a port in
// use, a GPU missing) still fails the start (exit 1).
#pragma once

#include <string>
#include <vector>

#include "daemon/config/config.h"

namespace fq::daemon {

/// One line per problem, each naming the file and line of the key (DaemonConfig::where), the
/// key, and the endpoint or file with what is wrong with it:
/// `fqd.toml:21: http.token_file /etc/fq/http.token: cannot be read: No such file or directory`.
/// Empty when there is none.
std::vector<std::string> config_problems(const DaemonConfig& config);

}  // namespace fq::daemon
