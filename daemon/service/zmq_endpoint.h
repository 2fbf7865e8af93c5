// The syntax of a ZeroMQ endpoint as libzmq parses it at bind or connect, checked without a
// socket, so that `fqd --check-config` names a malformed endpoint instead of the start failing
// at bind. Whether the address can be bound (an interface that exists, a free port) is left to
// the bind.
#pragma once

#include <string>

namespace fq::daemon {

/// How a socket uses an endpoint: a bound one may leave the port (tcp) or the path (ipc) to
/// the system with `*`; a connected one names its peer, possibly after a source address
/// (`tcp://SOURCE;HOST:PORT`).
enum class EndpointUse { kBind, kConnect };

/// What is wrong with `endpoint` for `use`, or "" when it is well-formed: tcp://HOST:PORT
/// (HOST a name, an address, [IPv6] or, to bind, `*`; PORT 0..65535 or, to bind, `*`),
/// ipc://PATH (at most 107 bytes: a unix socket address) or inproc://NAME.
std::string endpoint_problem(const std::string& endpoint, EndpointUse use);

}  // namespace fq::daemon
